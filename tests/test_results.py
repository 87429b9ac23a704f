"""The results table contract (usvtool/results.py): round trip, sorting, one-line errors."""

from __future__ import annotations

import pytest

from usvtool.errors import UsvError
from usvtool.results import Row, format_results, job_dir, read_results, write_results


def _rows():
    return [
        Row("ff01", "runs", "env1-head-on", "udwa", 1, "closest_distance_m", "23.7"),
        Row("0a02", "routes", "env1", "anyangle", None, "length_m", "699.03"),
        Row("0a02", "routes", "env1", "anyangle", None, "collision_free", "True"),
    ]


def test_round_trip_sorts_by_key_and_keeps_each_jobs_metric_order(tmp_path):
    path = tmp_path / "metrics.csv"
    write_results(path, _rows())
    assert path.read_text() == (
        "key,kind,case,method,seed,metric,value\n"
        "0a02,routes,env1,anyangle,,length_m,699.03\n"
        "0a02,routes,env1,anyangle,,collision_free,True\n"
        "ff01,runs,env1-head-on,udwa,1,closest_distance_m,23.7\n"
    )
    back = read_results(path)
    assert back == sorted(_rows(), key=lambda r: r.key)
    assert [r.number for r in back] == [699.03, 1.0, 23.7]
    assert job_dir(path, back[0]) == tmp_path / "routes" / "0a02"


def test_a_word_has_no_number():
    assert Row("k", "runs", "s", "dwa", 1, "failed_rules", "rule-14").number is None
    assert Row("k", "runs", "s", "dwa", 1, "x", "nan").number is None


@pytest.mark.parametrize(
    "text, message",
    [
        ("key,kind\n", "not a results table"),
        ("key,kind,case,method,seed,metric,value\na,routes,env1\n", "line 2: 3 columns"),
        ("key,kind,case,method,seed,metric,value\na,plans,env1,x,1,m,1\n", "kind 'plans'"),
        ("key,kind,case,method,seed,metric,value\na,routes,env1,x,one,m,1\n", "seed 'one'"),
        ("key,kind,case,method,seed,metric,value\na,routes,env1,x,1,m,\n", "value is empty"),
    ],
)
def test_bad_tables_give_one_line_naming_the_file_and_line(tmp_path, text, message):
    path = tmp_path / "t.csv"
    path.write_text(text)
    with pytest.raises(UsvError, match=message) as e:
        read_results(path)
    assert str(path) in str(e.value) and "\n" not in str(e.value)
    assert format_results([]) == "key,kind,case,method,seed,metric,value\n"


HEADER = "key,kind,case,method,seed,metric,value\n"


@pytest.mark.parametrize(
    "last, message",
    [
        ("0a,routes,env1,iwso,1,length_m,805.76\n",
         "job 0a, metric length_m: line 4 repeats line 2 (a job has one row a metric)"),
        ("0a,routes,env1,iwso,1,length_m,99999\n",
         "job 0a, metric length_m: line 2 says '805.76', line 4 says '99999' (a job has one "
         "row a metric)"),
        ("0a,routes,env2,iwso,1,fitness,3\n",
         "job 0a: line 2 says routes/env1/iwso seed 1, line 4 says routes/env2/iwso seed 1"),
    ],
)  # fmt: skip
def test_a_metric_given_twice_or_a_job_said_two_ways_is_refused_naming_the_lines(
        tmp_path, last, message):  # fmt: skip
    path = tmp_path / "t.csv"
    path.write_text(HEADER + "0a,routes,env1,iwso,1,length_m,805.76\n"
                    "0a,routes,env1,iwso,1,turns,2\n" + last)  # fmt: skip
    with pytest.raises(UsvError) as e:
        read_results(path)
    assert str(e.value) == f"{path}: {message}"


def test_the_same_metric_of_two_jobs_is_no_duplicate(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text(HEADER + "0a,routes,env1,iwso,1,length_m,805.76\n"
                    "0b,routes,env1,iwso,2,length_m,805.76\n")  # fmt: skip
    assert [r.key for r in read_results(path)] == ["0a", "0b"]
