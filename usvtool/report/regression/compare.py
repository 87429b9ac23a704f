"""``usvtool compare``: a results table compared with a baseline, group by group, and the
outputs written (:mod:`usvtool.report.regression`, docs/compare.md)."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from usvtool.errors import UsvError
from usvtool.report.output import write_together
from usvtool.report.regression import presentation
from usvtool.report.regression.groups import CLASSES, FAILING, Comparison, compare_group
from usvtool.report.regression.sides import Side
from usvtool.report.regression.tolerances import Tolerances, load_tolerances
from usvtool.results import TIMING_METRICS

FILES = ("index.html", "regression.json", "summary.md")  # index.html is renamed last


@dataclass(frozen=True)
class CompareOptions:
    """``tolerances``: the YAML file (None: ``BASELINE.tolerances.yaml`` when it exists, else the
    defaults); ``out_dir``: where the three outputs go (None: nothing is written)."""

    baseline: str
    current: str
    tolerances: str | None = None
    out_dir: str | None = None


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
        return presentation.markdown(self)

    def to_html(self) -> str:
        return presentation.html(self)


def compare(options: CompareOptions) -> CompareResult:
    """Compare the tables (:mod:`usvtool.report.regression`); write the outputs when ``out_dir``
    is given."""
    tolerances = load_tolerances(_tolerances_path(options))
    base = Side.read(options.baseline, refuse_invalid=True)
    head = Side.read(options.current, refuse_invalid=False)
    groups = sorted(base.values.keys() | head.values.keys(),
                    key=lambda g: (g[3] in TIMING_METRICS, g))  # fmt: skip
    kinds = {metric: base.kind(metric) for metric in {g[3] for g in groups}}
    comparisons = [compare_group(g, base, head, tolerances, kinds[g[3]]) for g in groups]
    result = CompareResult(options.baseline, options.current, tolerances, comparisons)
    if options.out_dir is not None:
        result.output = options.out_dir
        _write(result, Path(options.out_dir))
    return result


def _tolerances_path(options: CompareOptions) -> str | None:
    if options.tolerances is not None:
        return options.tolerances
    beside = Path(options.baseline).with_suffix(".tolerances.yaml")
    return str(beside) if beside.is_file() else None


def _write(result: CompareResult, out: Path) -> None:
    """Render everything, then write the three files together (``DIR`` made when missing,
    removed again when the writing fails; no link below it written through)."""
    if out.exists() and not out.is_dir():
        raise UsvError(f"{out}: exists and is not a directory")
    texts = (result.to_html(), result.to_json(), result.to_markdown())
    write_together(
        {out / name: text.encode("utf-8") for name, text in zip(FILES, texts, strict=True)}, out
    )
