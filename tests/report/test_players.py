"""The runs' players in the report (docs/report.md, "Players"): the document's Player block
(HTML only, escaped, the page's styles and script once and only with a player), the Imazu
section's players and the links to them from the table under its grid, the recorded-traffic
runs' players, and the worst run of each scene family per controller, chosen by hand."""

from __future__ import annotations

import json
import re
from html.parser import HTMLParser
from pathlib import Path

import pytest

from usvtool.report.animation.embed import REVEAL, run_player
from usvtool.report.animation.player import SCRIPT, STYLE
from usvtool.report.data import JobResults, Results
from usvtool.report.document import APPENDIX, HTML, MAIN, Cell, Player, Section, Table, anchor
from usvtool.report.page import html
from usvtool.report.runs import run_files
from usvtool.report.sections import imazu, traffic, worst_runs
from usvtool.results import Row
from usvtool.trace import read_events, read_trace, write_events

NASTY = "</script><script>alert(1)</script>"


def write_run(d: Path, target: str = "ts1", own: float = 12.0) -> None:
    """A run's trace and events: the own ship north at 6 m/s, ``target`` head-on 500 m ahead
    at 4 m/s, 5 s at 1 s steps; no encounter, no map."""
    d.mkdir(parents=True, exist_ok=True)
    lines = ["t,ship,x,y,heading,speed,yaw_rate"]
    for i in range(6):
        lines += [f"{i:.3f},own,0.000,{6.0 * i:.3f},0.000,6.0000,0.0000",
                  f"{i:.3f},{target},0.000,{500 - 4.0 * i:.3f},180.000,4.0000,0.0000"]
    (d / "trace.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")
    write_events(d / "trace.events.json", {"encounters": [], "thresholds": {"horizon_s": 120.0},
                 "run": {"own_length": own, "ships": [{"name": "own", "length": own},
                                                      {"name": target, "length": 10.0}],
                         "map": None, "wind_field": None, "goal": [0.0, 800.0],
                         "duration_s": 5.0}})  # fmt: skip


def job(root: Path, case: str, method: str, metrics: dict, family: str = "imazu",
        seed: int = 1, files: bool = True, target: str = "ts1") -> JobResults:  # fmt: skip
    d = root / "runs" / f"{case.replace('/', '-')}-{method}-{seed}"
    if files:
        write_run(d, target)
    else:
        d.mkdir(parents=True)
    rows = {m: Row("k", "runs", case, method, seed, m, str(v)) for m, v in metrics.items()}
    config = {"scene": {"family": family, "kind": case.split("/")[1], "scene": 0}}
    return JobResults(f"{case}-{method}-{seed}", "runs", case, method, seed, d, rows,
                      config=config)  # fmt: skip


def player_of(d: Path, id: str = "p1", title: str = "T", caption: str = "C") -> Player:
    return run_player(read_trace(d / "trace.csv"), read_events(d / "trace.events.json"),
                      d / "trace.events.json", id, title, caption)  # fmt: skip


class Tags(HTMLParser):
    """Every start tag with its attributes, and the text of each script element."""

    def __init__(self, text: str):
        super().__init__()
        self.tags: list[tuple[str, dict]] = []
        self.scripts: list[tuple[dict, str]] = []
        self._in: dict | None = None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))
        if tag == "script":
            self._in = dict(attrs)
            self.scripts.append((self._in, ""))

    def handle_data(self, data):
        if self._in is not None:
            attrs, text = self.scripts[-1]
            self.scripts[-1] = (attrs, text + data)

    def handle_endtag(self, tag):
        if tag == "script":
            self._in = None


# --- the block and the page -----------------------------------------------------------------


def test_a_player_is_placed_html_only_and_holds_a_players_div(tmp_path):
    write_run(tmp_path / "r")
    p = player_of(tmp_path / "r")
    assert p.placement == HTML and p.fragment.startswith('<div class="usv-player"')
    with pytest.raises(ValueError, match="placed 'main'"):
        Player("x", "t", "c", p.fragment, MAIN)
    with pytest.raises(ValueError, match="placed 'appendix'"):
        Player("x", "t", "c", p.fragment, APPENDIX)
    with pytest.raises(ValueError, match="not a player's div"):
        Player("x", "t", "c", "<b>markup</b>")


def test_anchors_are_ids_of_safe_characters_and_never_the_same_for_two_names():
    assert anchor("imazu-run", "imazu/05/s000", "udwa+") == "imazu-run_imazu~2F05~2Fs000_udwa+"
    assert anchor("a", "b_c") != anchor("a_b", "c")
    assert re.fullmatch(r"[A-Za-z0-9._+~-]+", anchor("x", '"><script>', "é"))


def test_the_page_holds_the_players_script_and_styles_once_and_escapes_every_input(tmp_path):
    write_run(tmp_path / "a", target=NASTY)
    write_run(tmp_path / "b")
    players = [player_of(tmp_path / "a", "pa", f"title {NASTY}", f"caption {NASTY}"),
               player_of(tmp_path / "b", "pb")]  # fmt: skip
    link = Table("links", "Links", "c", ["run"], [[Cell("a's run", link="pa")]])
    sections = [Section("one", "One", ["text"], [link, players[0]]),
                Section("two", "Two", blocks=[players[1]], subsections=[
                    Section("sub", "Sub", blocks=[], placement=HTML)])]  # fmt: skip
    page = html("Report", "sub", sections)
    tags = Tags(page)
    code = [text for attrs, text in tags.scripts if not attrs]
    assert code == [SCRIPT + REVEAL]  # one script, the players'
    data = [text for attrs, text in tags.scripts if attrs.get("type") == "application/json"]
    assert len(data) == 2 and json.loads(data[0])["ships"][1]["n"] == NASTY
    assert page.count(STYLE) == 1
    assert NASTY not in page  # the name escaped in the data, the title and caption by the page
    assert f"title {NASTY}".replace("<", "&lt;").replace(">", "&gt;") in page
    assert "<script>alert" not in page
    # each player its own folded <details> of its id; the cell links to it
    assert [a["id"] for t, a in tags.tags if t == "details" and "usv-run" in a.get("class", "")
            ] == ["pa", "pb"]  # fmt: skip
    assert '<a href="#pa">a&#39;s run</a>' in page
    for _, attrs in tags.tags:  # nothing outside the page
        for name in ("src", "href"):
            assert attrs.get(name) is None or attrs[name].startswith(("data:", "#")), attrs


def test_a_page_without_players_and_the_print_page_hold_no_script(tmp_path):
    write_run(tmp_path / "a")
    plain = html("R", "s", [Section("one", "One", ["text"])])
    assert "<script" not in plain and "usv-player" not in plain
    with_player = [Section("one", "One", ["text"], [
        player_of(tmp_path / "a"), Table("t", "T", "c", ["x"], [[Cell("run", link="p1")]])])]
    printed = html("R", "s", with_player, "print")
    assert "<script" not in printed and "usv-player" not in printed and "<details" not in printed
    assert 'href="#p1"' not in printed and ">run<" in printed  # the link's text, no link


def test_the_player_script_starts_a_folded_player_only_when_its_details_opens():
    assert "folded(all[i])" in SCRIPT and 'addEventListener("toggle"' in SCRIPT


# --- the sections ---------------------------------------------------------------------------


OK = {"arrived": True, "arrival_time_s": 140.0, "compliant": 1, "compliant_excused": 0,
      "noncompliant": 0, "not_judged": 0}  # fmt: skip


def test_the_imazu_section_plays_every_run_with_its_files_and_links_the_grid_to_them(tmp_path):
    jobs = [job(tmp_path, "imazu/01/s000", "dwa", {**OK, "closest_distance_m": 41.25}),
            job(tmp_path, "imazu/01/s000", "udwa", {"arrived": False, "collision": "ts1",
                                                    "closest_distance_m": 3.5}),
            job(tmp_path, "imazu/02/s000", "dwa", {**OK, "closest_distance_m": 60.0},
                files=False)]  # fmt: skip
    s = imazu.section(Results(jobs, [], order=("dwa", "udwa")))
    played = next(sub for sub in s.subsections if sub.id == "imazu-players")
    assert played.placement == HTML
    ids = [b.id for b in played.blocks]
    assert ids == [imazu.player_id("imazu/01/s000", "dwa"),
                   imazu.player_id("imazu/01/s000", "udwa")]  # the one without files: none
    assert all(isinstance(b, Player) for b in played.blocks)
    nav = next(b for b in s.blocks if b.id == "imazu-players-table")
    assert nav.placement == HTML
    assert [[(c.text, c.link) for c in row] for row in nav.rows] == [
        [("01 HO", ""), ("▶ 41 m", ids[0]), ("▶ collided", ids[1])],
        [("02 ?", ""), ("60 m", ""), ("no run", "")]]  # fmt: skip
    assert imazu.ANIMATED in s.paragraphs  # in the PDF too
    page = html("R", "s", [s])
    assert page.count("<script>") == 1 and page.count('class="usv-player"') == 2
    assert "usv-player" not in html("R", "s", [s], "print")


def test_the_worst_run_is_the_collision_then_no_arrival_then_the_closest(tmp_path):
    def run(case, method, metrics, seed=1):
        return job(tmp_path, case, method, metrics, "emergency", seed, files=False)

    a = run("emergency/head-on/s000", "udwa", {**OK, "closest_distance_m": 10.0})
    b = run("emergency/head-on/s001", "udwa", {**OK, "closest_distance_m": 5.0})
    c = run("emergency/crossing/s000", "udwa", {"arrived": False, "closest_distance_m": 50.0})
    d = run("emergency/crossing/s001", "udwa", {"arrived": False, "collision": "ts1",
                                                "closest_distance_m": 30.0})  # fmt: skip
    e = run("emergency/head-on/s002", "udwa", {**OK})  # no closest distance: after the known
    assert worst_runs.worst([a, b, c, d, e]) is d  # collided, whatever its distance
    assert worst_runs.worst([a, b, c, e]) is c  # did not arrive, though 50 m off
    assert worst_runs.worst([a, b, e]) is b  # 5 m < 10 m
    assert worst_runs.worst([e, a]) is a
    f = run("emergency/head-on/s000", "ccdwa", {**OK, "closest_distance_m": 7.0})
    g = run("emergency/head-on/s000", "udwa", {**OK, "closest_distance_m": 4.0}, seed=2)
    ais = job(tmp_path, "ny/under-way/s001", "udwa", {**OK, "closest_distance_m": 0.5}, "ais",
              files=False)  # fmt: skip
    bundled = JobResults("bundled", "runs", "emergency-head-on", "udwa", 1, tmp_path, {
        "closest_distance_m": Row("k", "runs", "x", "udwa", 1, "closest_distance_m", "0.1")})
    chosen = worst_runs.worst_runs(Results([a, b, g, f, ais, bundled], [],
                                           order=("ccdwa", "udwa")))  # fmt: skip
    assert {k: (j.key, n) for k, (j, n) in chosen.items()} == {
        ("emergency", "ccdwa"): (f.key, 1), ("emergency", "udwa"): (g.key, 3)}
    assert list(chosen) == [("emergency", "ccdwa"), ("emergency", "udwa")]


def test_the_worst_runs_section_plays_them_and_links_the_main_imazu_entrys_to_its_players(
        tmp_path):  # fmt: skip
    jobs = [job(tmp_path, "emergency/head-on/s000", "udwa", {**OK, "closest_distance_m": 9.0},
                "emergency"),
            job(tmp_path, "emergency/head-on/s001", "udwa", {**OK, "closest_distance_m": 2.0},
                "emergency"),
            job(tmp_path, "imazu/01/s000", "udwa", {**OK, "closest_distance_m": 41.0}),
            job(tmp_path, "imazu/02/s000", "udwa", {**OK, "closest_distance_m": 31.0})]
    s = worst_runs.section(Results(jobs, [], order=("udwa",)))
    table = s.blocks[0]
    assert table.placement == MAIN and s.placement == MAIN
    rows = [[c.text for c in row] for row in table.rows]
    assert rows == [["emergency", "udwa", "2", "emergency/head-on/s001 (seed 1)", "arrived",
                     "2.0"],
                    ["imazu", "udwa", "2", "imazu/02/s000 (seed 1)", "arrived", "31.0"]]
    links = [row[3].link for row in table.rows]
    assert links == [worst_runs.player_id("emergency", "udwa"),
                     imazu.player_id("imazu/02/s000", "udwa")]  # the Imazu section's player
    played = s.subsections[0]
    assert played.placement == HTML and [b.id for b in played.blocks] == [links[0]]
    assert "HTML report" in s.paragraphs[0]  # the line in the PDF
    assert worst_runs.section(Results([], [])) is None


def _traffic_helper():
    """test_traffic.py's hand-built AIS runs (its module, loaded by path: tests are no
    package)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("test_traffic_helpers",
                                                  Path(__file__).with_name("test_traffic.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_recorded_traffic_runs_are_played_and_linked_from_the_runs_table(tmp_path):
    t = _traffic_helper()
    dwa = t.run(tmp_path, "dwa", {**OK, "closest_distance_m": 12.0}, {f"ais-{t.SHARK}": 30.0})
    udwa = t.run(tmp_path, "udwa", {"arrived": False, "closest_distance_m": 8.0},
                 {f"ais-{t.SHARK}": 8.0})  # fmt: skip
    write_run(dwa.dir, target=f"ais-{t.SHARK}")  # udwa's run has no trace: no player
    s = traffic.section(Results([dwa, udwa], [], ("dwa", "udwa")))
    played = next(sub for sub in s.subsections if sub.id == "traffic-players")
    pid = traffic.player_id(t.CASE, "dwa")
    assert played.placement == HTML and [b.id for b in played.blocks] == [pid]
    runs = next(b for b in s.blocks if b.id == "traffic-runs")
    assert [(r[1].text, r[1].link) for r in runs.rows] == [
        ("recorded", ""), ("dwa", pid), ("udwa", "")]
    assert traffic.ANIMATED in s.paragraphs
    assert run_files(dwa).trace is run_files(dwa).trace  # read once per report
