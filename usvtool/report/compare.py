"""Regression reports: compare a current results table with a baseline (``usvtool compare``).

Both tables are results tables (:mod:`usvtool.results`). Rows are matched by group (kind, case,
method, metric) and each side's value of a group is one figure over its jobs (seeds):

- ``median`` of the numbers (lengths, turns, times, costs, ...);
- ``mean`` when every value is ``True``/``False``: the rate of ``True`` (a median of 0/1 values
  is no rate);
- ``share`` for :data:`EVENTS` (``collision``, whose row is there only when the ship hit
  something, the value naming what): the fraction of the case and method's jobs with a row;
- ``words`` otherwise (``failed_rules``, ...): the sorted set of the ``;``-separated words.

A metric of :data:`ABSENT_IS_NONE` that a side lacks while it has the case and method is that
side's "none" (a share of 0, no words), not a missing group.

Each metric's values must be of its kind (:mod:`usvtool.report.values`: the contract's finite
numbers, ``True``/``False`` or words; a metric it does not list takes the baseline's kind). A
baseline holding a value that is not of its kind is refused; a group of the current table
holding one is ``invalid`` (its figure: those values), whatever the other values are.

Each metric has a :class:`Rule` (:data:`RULES`; unknown metrics are informational): the better
direction and a tolerance. With ``change = head - base`` and ``allowed = max(relative * |base|,
absolute)``, a group is ``ok`` when ``|change| <= allowed``, else ``improved`` or ``regressed``
by the direction, or ``changed`` for an informational metric (words: ``ok`` when equal, else
``changed``); ``change`` and ``allowed`` are rounded to 12 significant digits first. A group
only in the baseline is ``missing``, only in the current table ``new``. Timings
(:data:`usvtool.results.TIMING_METRICS`, from ``timings.csv`` beside either table) are
classified the same way but count towards the status only when the tolerances file says
``count_timings: true``. The status is 1 when a counted group is invalid, regressed or went
missing.

The tolerances file (YAML, ``BASELINE`` with the suffix ``.tolerances.yaml`` unless given)::

    count_timings: false
    metrics:
      length_m: {relative: 0.05}          # the other fields keep their defaults
      my_metric: {better: higher, relative: 0.01, absolute: 0.1}

Outputs (:func:`compare` with ``out_dir``, renamed into place together): ``index.html``,
``regression.json`` and ``summary.md``. docs/compare.md describes them.
"""

from __future__ import annotations

import json
import math
import statistics
from collections import defaultdict
from dataclasses import asdict, dataclass, field
from pathlib import Path

from usvtool import __version__
from usvtool.errors import UsvError
from usvtool.report import values
from usvtool.report.output import write_together
from usvtool.results import TIMING_METRICS, Row, read_results, timings_path

LOWER, HIGHER, NONE = "lower", "higher", "none"
#: The classes, in the order the reports list them.
CLASSES = ("invalid", "regressed", "missing", "improved", "new", "changed", "ok")
FAILING = ("invalid", "regressed", "missing")
FILES = ("index.html", "regression.json", "summary.md")  # index.html is renamed last
#: Rows of the Markdown summary's table at most.
MARKDOWN_ROWS = 30
MARKDOWN_COLUMNS = ("class", "kind", "case", "method", "metric", "BASE", "HEAD", "change",
                    "tolerance")  # fmt: skip
MARKDOWN_CELLS = ("status", "kind", "case", "method", "metric", "base", "head", "change",
                  "tolerance")  # fmt: skip


@dataclass(frozen=True)
class Rule:
    """A metric's better direction (``lower``, ``higher`` or ``none``: informational) and its
    tolerance, ``max(relative * |base|, absolute)``."""

    better: str = NONE
    relative: float = 0.0
    absolute: float = 0.0


INFO = Rule()
RULES: dict[str, Rule] = {
    # routes (usvtool metrics' ROUTE_COLUMNS) and the same metrics of runs
    "length_m": Rule(LOWER, 0.02, 0.01),
    "length_ratio": Rule(LOWER, 0.02, 1e-4),
    "turns": Rule(LOWER, 0.10, 0.5),
    "mot": Rule(LOWER, 0.05, 0.01),
    "fitness": Rule(LOWER, 0.02, 0.01),
    "collision_free": Rule(HIGHER),
    "attempt": INFO,
    # runs (RUN_COLUMNS)
    "arrived": Rule(HIGHER),
    "collision": Rule(LOWER),
    "arrival_time_s": Rule(LOWER, 0.02, 0.1),
    "closest_distance_m": Rule(HIGHER, 0.02, 0.01),
    "average_distance_m": Rule(HIGHER, 0.02, 0.01),
    "domain_intrusion_s": Rule(LOWER, 0.05, 0.1),
    "encounters": INFO,
    "judged": INFO,
    "compliant": Rule(HIGHER),
    "failed_rules": INFO,
    "reference_controller": INFO,
    "closest_distance_rate": Rule(HIGHER, 0.05, 0.01),
    "average_distance_rate": Rule(HIGHER, 0.05, 0.01),
    # functions
    "final_cost": Rule(LOWER, 0.05, 1e-6),
    # timings (timings.csv): reported, counted only with count_timings
    "wall_time_s": Rule(LOWER, 0.25, 0.05),
    "planning_time_s": Rule(LOWER, 0.25, 0.05),
    # the identity columns of usvtool metrics, should a table carry them as metrics
    **dict.fromkeys(("chart", "algorithm", "run", "scenario", "controller", "seed"), INFO),
}
#: Metrics whose row marks an event (its value names it): compared as a share of the jobs.
EVENTS = ("collision",)
#: Metrics whose absence from a job means "none" (no collision, no failed rule).
ABSENT_IS_NONE = ("collision", "failed_rules")
#: The distinct values an invalid group's figure shows at most.
INVALID_SHOWN = 3


@dataclass(frozen=True)
class CompareOptions:
    """``tolerances``: the YAML file (None: ``BASELINE.tolerances.yaml`` when it exists, else the
    defaults); ``out_dir``: where the three outputs go (None: nothing is written)."""

    baseline: str
    current: str
    tolerances: str | None = None
    out_dir: str | None = None


@dataclass(frozen=True)
class Tolerances:
    """The rules in force and whether timings count; ``path`` the file they came from."""

    rules: dict[str, Rule] = field(default_factory=lambda: dict(RULES))
    count_timings: bool = False
    path: str | None = None

    def rule(self, metric: str) -> Rule:
        return self.rules.get(metric, INFO)


@dataclass(frozen=True)
class Comparison:
    """One group of both tables: each side's figure (None: absent) over ``n`` jobs, how many of
    the current values are ``invalid``, the change, the tolerance ``allowed`` and the class
    (module docstring)."""

    kind: str
    case: str
    method: str
    metric: str
    timing: bool
    better: str
    aggregate: str
    base: float | str | None
    head: float | str | None
    n_base: int
    n_head: int
    invalid: int
    change: float | None
    relative_change: float | None
    relative: float
    absolute: float
    allowed: float | None
    status: str
    counted: bool

    @property
    def label(self) -> str:
        return f"{self.kind}/{self.case}/{self.method}/{self.metric}"

    def to_dict(self) -> dict:
        data = asdict(self)
        data["class"] = data.pop("status")
        return data


@dataclass
class CompareResult:
    """Every group, sorted by (timing, kind, case, method, metric)."""

    baseline: str
    current: str
    tolerances: Tolerances
    comparisons: list[Comparison]
    output: str | None = None

    def counts(self, timing: bool = False) -> dict[str, int]:
        found = [c.status for c in self.comparisons if c.timing == timing]
        return {name: found.count(name) for name in CLASSES}

    def failures(self) -> list[Comparison]:
        return [c for c in self.comparisons if c.counted and c.status in FAILING]

    @property
    def status(self) -> int:
        """The exit status: 1 when a counted group is invalid, regressed or went missing."""
        return 1 if self.failures() else 0

    def summary(self) -> dict:
        failures = self.failures()
        return {
            "output": self.output,
            "files": list(FILES) if self.output is not None else [],
            "baseline": self.baseline,
            "current": self.current,
            "tolerances": self.tolerances.path,
            "count_timings": self.tolerances.count_timings,
            "groups": sum(not c.timing for c in self.comparisons),
            "counts": self.counts(),
            "timings": self.counts(timing=True),
            "regressed": [c.label for c in failures if c.status == "regressed"],
            "missing": [c.label for c in failures if c.status == "missing"],
            "invalid": [c.label for c in failures if c.status == "invalid"],
            "status": self.status,
        }

    def to_json(self) -> str:
        data = {**self.summary(), "groups": [c.to_dict() for c in self.comparisons]}
        del data["output"], data["files"]
        return json.dumps(data, indent=1, allow_nan=False) + "\n"

    def to_markdown(self) -> str:
        return _markdown(self)

    def to_html(self) -> str:
        from usvtool.report.templating import render

        rows = [_cells(c) for c in _report_order(c for c in self.comparisons if not c.timing)]
        timings = [_cells(c) for c in _report_order(c for c in self.comparisons if c.timing)]
        return render(
            "regression.html.j2", verdict=_verdict(self), inputs=_inputs(self),
            counts=self.counts(), timing_counts=self.counts(timing=True),
            count_timings=self.tolerances.count_timings, rows=rows, timings=timings,
            version=__version__,
        )  # fmt: skip


def compare(options: CompareOptions) -> CompareResult:
    """Compare the tables (module docstring); write the outputs when ``out_dir`` is given."""
    tolerances = load_tolerances(_tolerances_path(options))
    base = _Side.read(options.baseline, refuse_invalid=True)
    head = _Side.read(options.current, refuse_invalid=False)
    groups = sorted(base.values.keys() | head.values.keys(),
                    key=lambda g: (g[3] in TIMING_METRICS, g))  # fmt: skip
    kinds = {metric: base.kind(metric) for metric in {g[3] for g in groups}}
    comparisons = [_compare_group(g, base, head, tolerances, kinds[g[3]]) for g in groups]
    result = CompareResult(options.baseline, options.current, tolerances, comparisons)
    if options.out_dir is not None:
        result.output = options.out_dir
        _write(result, Path(options.out_dir))
    return result


def load_tolerances(path: str | None) -> Tolerances:
    """The defaults (:data:`RULES`) updated from the YAML file ``path`` (None: the defaults)."""
    if path is None:
        return Tolerances()
    from usvtool.yamlfile import read_yaml

    data = read_yaml(path)
    data = {} if data is None else data
    if not isinstance(data, dict):
        raise UsvError(f"{path}: must be a mapping with count_timings and metrics")
    unknown = sorted(set(map(str, data)) - {"count_timings", "metrics"})
    if unknown:
        raise UsvError(f"{path}: unknown key {unknown[0]!r} (expected count_timings, metrics)")
    count_timings = data.get("count_timings", False)
    if not isinstance(count_timings, bool):
        raise UsvError(f"{path}: count_timings: must be true or false")
    metrics = data.get("metrics") or {}
    if not isinstance(metrics, dict):
        raise UsvError(f"{path}: metrics: must be a mapping of metric names")
    rules = dict(RULES)
    for name, spec in metrics.items():
        rules[str(name)] = _rule(path, f"metrics.{name}", spec, rules.get(str(name), INFO))
    return Tolerances(rules, count_timings, str(path))


def _rule(path, where: str, spec, default: Rule) -> Rule:
    if not isinstance(spec, dict):
        raise UsvError(f"{path}: {where}: must be a mapping (better, relative, absolute)")
    unknown = sorted(set(map(str, spec)) - {"better", "relative", "absolute"})
    if unknown:
        raise UsvError(f"{path}: {where}: unknown key {unknown[0]!r} "
                       "(expected better, relative, absolute)")  # fmt: skip
    better = spec.get("better", default.better)
    if better not in (LOWER, HIGHER, NONE):
        raise UsvError(f"{path}: {where}.better: {better!r} is not lower, higher or none")
    values = {}
    for key in ("relative", "absolute"):
        value = spec.get(key, getattr(default, key))
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise UsvError(f"{path}: {where}.{key}: {value!r} is not a number")
        if not math.isfinite(value) or value < 0:
            raise UsvError(f"{path}: {where}.{key}: {value!r} must be a finite number >= 0")
        values[key] = float(value)
    return Rule(better, **values)


def _tolerances_path(options: CompareOptions) -> str | None:
    if options.tolerances is not None:
        return options.tolerances
    beside = Path(options.baseline).with_suffix(".tolerances.yaml")
    return str(beside) if beside.is_file() else None


Group = tuple[str, str, str, str]


@dataclass(frozen=True)
class _Figure:
    """A side's figure of a group: its aggregate, value, how many jobs (or values) it is over,
    and how many of them are invalid (the value then lists those, as words)."""

    aggregate: str
    value: float | str
    n: int
    invalid: int = 0


@dataclass
class _Side:
    """One table (and its timings): the rows of each group, the jobs of each case and method."""

    values: dict[Group, list[Row]]
    jobs: dict[tuple[str, str, str], int]

    @classmethod
    def read(cls, table: str, refuse_invalid: bool) -> _Side:
        """Read the table and the timings beside it; with ``refuse_invalid``, refuse either
        when it holds a value not of its metric's kind (:mod:`usvtool.report.values`)."""
        rows = _read(table, refuse_invalid)
        timings = timings_path(table)
        if timings.is_file() and timings.resolve() != Path(table).resolve():
            rows += _read(timings, refuse_invalid)
        groups: dict[Group, list[Row]] = defaultdict(list)
        keys: dict[tuple[str, str, str], set[str]] = defaultdict(set)
        for r in rows:
            groups[r.group].append(r)
            keys[r.group[:3]].add(r.key)
        return cls(dict(groups), {job: len(k) for job, k in keys.items()})

    def kind(self, metric: str) -> str | None:
        """The metric's kind: the contract's, else the one of this side's values."""
        return values.kind(metric) or values.inferred(
            [r for g, rows in self.values.items() if g[3] == metric for r in rows]
        )

    def figure(self, group: Group, kind: str | None) -> _Figure | None:
        """The figure of a group on this side, its values being of ``kind``; None when absent."""
        rows = self.values.get(group)
        jobs = self.jobs.get(group[:3], 0)
        metric = group[3]
        if rows is None and not (metric in ABSENT_IS_NONE and jobs):
            return None
        rows = rows or []
        if metric in EVENTS:
            return _Figure("share", len({r.key for r in rows}) / jobs, jobs)
        aggregate = {values.NUMBER: "median", values.BOOLEAN: "mean"}.get(kind)
        bad = [r.value for r in rows if not values.valid(kind, r.value)]
        if bad:
            shown = sorted(set(bad))
            text = ";".join(shown[:INVALID_SHOWN]) + (";…" if len(shown) > INVALID_SHOWN else "")
            return _Figure(aggregate, text, len(rows), len(bad))
        numbers = [r.number for r in rows]
        if rows and all(r.value in ("True", "False") for r in rows):
            return _Figure("mean", statistics.fmean(numbers), len(rows))
        if rows and None not in numbers:
            return _Figure("median", float(statistics.median(numbers)), len(rows))
        words = sorted({w for r in rows for w in r.value.split(";") if w})
        return _Figure("words", ";".join(words), len(rows))


def _read(path: str | Path, refuse_invalid: bool) -> list[Row]:
    rows = read_results(path)
    bad = values.invalid(rows) if refuse_invalid else []
    if bad:
        raise UsvError(values.refusal(path, bad))
    return rows


def _compare_group(group: Group, base: _Side, head: _Side, tolerances: Tolerances,
                   kind: str | None) -> Comparison:  # fmt: skip
    metric = group[3]
    rule = tolerances.rule(metric)
    timing = metric in TIMING_METRICS
    b, h = base.figure(group, kind), head.figure(group, kind)
    change = relative_change = allowed = None
    if h is not None and h.invalid:
        status = "invalid"
    elif b is None or h is None:
        status = "new" if b is None else "missing"
    elif isinstance(b.value, str) or isinstance(h.value, str):
        status = "ok" if b.value == h.value else "changed"
    else:
        change = _significant(h.value - b.value)
        relative_change = _significant(change / abs(b.value)) if b.value else None
        allowed = _significant(max(rule.relative * abs(b.value), rule.absolute))
        status = _classify(rule.better, change, allowed)
    return Comparison(
        *group, timing=timing, better=rule.better, aggregate=(b or h).aggregate,
        base=None if b is None else b.value, head=None if h is None else h.value,
        n_base=0 if b is None else b.n, n_head=0 if h is None else h.n,
        invalid=0 if h is None else h.invalid, change=change,
        relative_change=relative_change, relative=rule.relative, absolute=rule.absolute,
        allowed=allowed, status=status,
        counted=not timing or tolerances.count_timings,
    )  # fmt: skip


def _significant(x: float) -> float:
    """``x`` to 12 significant digits, so that a change equal to the tolerance in the files'
    decimals is equal here too (``0.714 - 0.7`` and ``0.02 * 0.7`` are both 0.014)."""
    return float(f"{x:.12g}")


def _classify(better: str, change: float, allowed: float) -> str:
    if abs(change) <= allowed:
        return "ok"
    if better == NONE:
        return "changed"
    worse = change > 0 if better == LOWER else change < 0
    return "regressed" if worse else "improved"


def _write(result: CompareResult, out: Path) -> None:
    """Render everything, then write the three files together (``DIR`` made when missing,
    removed again when the writing fails)."""
    if out.exists() and not out.is_dir():
        raise UsvError(f"{out}: exists and is not a directory")
    texts = (result.to_html(), result.to_json(), result.to_markdown())
    write_together(
        {out / name: text.encode("utf-8") for name, text in zip(FILES, texts, strict=True)}
    )


# ---- presentation (HTML and Markdown share the cells) ----


def _report_order(comparisons) -> list[Comparison]:
    return sorted(comparisons, key=lambda c: (CLASSES.index(c.status), c.label))


def _number(x: float) -> str:
    return str(int(x)) if x.is_integer() and abs(x) < 1e15 else format(x, ".6g")


def _figure(value: float | str | None) -> str:
    if value is None:
        return "—"
    if isinstance(value, str):
        return value or "(none)"
    return _number(value)


def _cells(c: Comparison) -> dict[str, str]:
    """The display text of a comparison's columns, and its class."""
    change = ""
    if c.change:
        change = ("+" if c.change > 0 else "") + _number(c.change)
        if c.relative_change is not None:
            change += f" ({c.relative_change:+.1%})".replace("%", " %")
    elif c.change == 0:
        change = "0"
    elif c.status == "invalid":
        expected = "True/False" if c.aggregate == "mean" else "numbers"
        change = f"{c.invalid} of {c.n_head} not {expected}"
    elif c.status == "changed":
        change = "changed"
    n = str(c.n_base) if c.n_base == c.n_head else f"{c.n_base} → {c.n_head}"
    if c.n_base == 0 or c.n_head == 0:
        n = str(c.n_base or c.n_head)
    return {
        "status": c.status, "kind": c.kind, "case": c.case, "method": c.method,
        "metric": c.metric, "better": c.better, "over": f"{c.aggregate} of {n}",
        "base": _figure(c.base), "head": _figure(c.head), "change": change,
        "tolerance": "" if c.allowed is None else "±" + _number(c.allowed),
    }  # fmt: skip


def _verdict(result: CompareResult) -> str:
    counts = result.counts()
    if result.tolerances.count_timings:
        for name, n in result.counts(timing=True).items():
            counts[name] += n
    text = "FAIL" if result.status else "PASS"
    failed = [f"{counts[name]} {name}" for name in FAILING if counts[name]]
    return f"{text}: {', '.join(failed)}" if failed else text


def _inputs(result: CompareResult) -> list[tuple[str, str]]:
    return [("baseline", result.baseline), ("current", result.current),
            ("tolerances", result.tolerances.path or "(built-in defaults)")]  # fmt: skip


def _counts_line(counts: dict[str, int]) -> str:
    return ", ".join(f"{n} {name}" for name, n in counts.items())


def _markdown(result: CompareResult) -> str:
    """The short summary for CI logs (docs/compare.md)."""
    shown = ("invalid", "regressed", "missing", "improved")
    timings = "counted" if result.tolerances.count_timings else "not counted"
    lines = [
        f"## usvtool compare: {_verdict(result)}",
        "",
        f"Groups: {_counts_line(result.counts())}.",
        f"Timings ({timings}): {_counts_line(result.counts(timing=True))}.",
        "",
        f"- baseline: `{result.baseline}`",
        f"- current: `{result.current}`",
        f"- tolerances: `{result.tolerances.path}`" if result.tolerances.path
        else "- tolerances: built-in defaults",
    ]
    listed = [c for c in _report_order(result.comparisons) if c.counted and c.status in shown]
    if listed:
        lines += ["", "| " + " | ".join(MARKDOWN_COLUMNS) + " |",
                  "|---|---|---|---|---|---:|---:|---:|---:|"]  # fmt: skip
        for c in listed[:MARKDOWN_ROWS]:
            cells = _cells(c)
            lines.append("| " + " | ".join(_md(cells[k]) for k in MARKDOWN_CELLS) + " |")
        if len(listed) > MARKDOWN_ROWS:
            lines += ["", f"… and {len(listed) - MARKDOWN_ROWS} more: see regression.json "
                      "or index.html."]  # fmt: skip
    return "\n".join(lines) + "\n"


def _md(text: str) -> str:
    return text.replace("|", "\\|")
