"""The report's first page: what was compared, the headline verdicts of the papers' claims (for
the papers' own methods; :func:`usvtool.report.judging.paper_verdicts`, computed once) and
the caveats, what differs from the papers' set-ups."""

from __future__ import annotations

import math
import re
from collections import Counter

from usvtool.report import judging
from usvtool.report.data import Results
from usvtool.report.document import HTML, Cell, Section, Table
from usvtool.report.papers import IWSO_DWA_TABLE_1, PAPERS
from usvtool.report.sections import baselines, claims


def _natural(case: str) -> tuple:
    """F2 before F10."""
    return tuple(int(t) if t.isdigit() else t for t in re.split(r"(\d+)", case))


def _by_seeds(results: Results, kind: str) -> str:
    """The cases grouped by their runs per method: ``env1, env2: 25 runs a method; grid20: 50
    runs a method``."""
    per = Counter((j.case, j.method) for j in results.select(kind))
    seeds: dict[int, list[str]] = {}
    for case in sorted(results.cases(kind), key=_natural):
        seeds.setdefault(max(n for (c, _), n in per.items() if c == case), []).append(case)
    return "; ".join(f"{_names(cases)}: {n} run{'s' * (n > 1)} a method"
                     for n, cases in seeds.items())  # fmt: skip


def _names(cases: list[str]) -> str:
    """``F1-F10`` for a run of numbered names, else every name (never "4 others": a reader
    must see which cases a count is of).

    >>> _names(["F1", "F2", "F3"]), _names(["env1", "env2"]), _names(list("abcd"))
    ('F1-F3', 'env1, env2', 'a, b, c, d')
    """
    numbered = [re.fullmatch(r"([A-Za-z]+)(\d+)", c) for c in cases]
    if len(cases) > 2 and all(numbered) and len({m.group(1) for m in numbered}) == 1:
        numbers = [int(m.group(2)) for m in numbered]
        if numbers == list(range(numbers[0], numbers[0] + len(numbers))):
            return f"{cases[0]}-{cases[-1]}"
    return ", ".join(cases)


def _families(results: Results) -> str:
    """The scene families run: each with its kinds and scenes per kind."""
    scenes: dict[str, dict[str, set]] = {}
    for j in results.select("runs"):
        if j.case.count("/") == 2:
            family, kind, _ = j.case.split("/")
            scenes.setdefault(family, {}).setdefault(kind, set()).add(j.case)
    parts = []
    for family, kinds in sorted(scenes.items()):
        counts = [len(c) for c in kinds.values()]
        low, high = min(counts), max(counts)
        each = f"{low}" if low == high else f"{low}-{high}"
        parts.append(f"{family} ({len(kinds)} kind{'s' * (len(kinds) > 1)} x {each} "
                     f"scene{'s' * (high > 1)})")
    return ", ".join(parts)


def compared(results: Results) -> str:
    """One paragraph: the papers, and our routes, runs and functions by method and case."""
    parts = []
    for kind, what in (("routes", "routes of {} optimizers and planners"),
                       ("functions", "benchmark-function runs of {} optimizers")):
        if jobs := results.select(kind):
            parts.append(f"{len(jobs)} {what.format(len(results.methods(kind)))} "
                         f"({_by_seeds(results, kind)})")
    if runs := results.select("runs"):
        text = f"{len(runs)} simulated runs of {len(results.methods('runs'))} controllers"
        if families := _families(results):
            text += f" on the scene families {families}, paired by scene"
        if single := {j.case for j in runs if "/" not in j.case}:
            text += (f", and on {len(single)} bundled scenario{'s' * (len(single) > 1)} (one "
                     "run each, as illustrations)")
        parts.append(text)
    papers = ", ".join(f"{p.id} ({_cited(p.citation)})" for p in PAPERS.values())
    return (f"Compared: the claims and published figures of {len(PAPERS)} papers, {papers}, "
            f"with {'; '.join(parts) or 'no runs'}.")


def _cited(citation: str) -> str:
    """``Liang & Liu 2023``, ``Liu et al. 2023`` from ``Authors, Title, Journal Year, ...``.

    >>> _cited("Liu, Zhang, Ma & Pan, Path Planning, J. Mar. Sci. Eng. 2023, 11, 2292")
    'Liu et al. 2023'
    """
    parts = citation.split(", ")
    last = next((i for i, part in enumerate(parts) if "&" in part), 0)
    year = re.search(r"\b(1[89]|20)\d\d\b", citation)
    authors = parts[0] if last == 0 else f"{parts[0]} et al."
    return f"{authors} {year.group(0)}" if year else authors


def smallest_p(n: int) -> float:
    """The smallest two-sided p of the Mann-Whitney U test of n runs against n: every run of
    one side below every run of the other, 2 / C(2n, n).

    >>> round(smallest_p(5), 5), f"{smallest_p(10):.2e}"
    (0.00794, '1.08e-05')
    """
    return 2.0 / math.comb(2 * n, n)


def caveats(results: Results, verdicts: list[judging.Verdict]) -> list[str]:
    """What differs from the papers' set-ups, in short sentences."""
    out = [
        "Our env1, env2 and grid20 are rebuilt from the papers' descriptions, not their maps: "
        "compare orders and trends, not values.",
        "The UDWA emergencies and wind fields run a 15 m USV for minutes (the paper's wind "
        "runs take an hour), the IWSO-DWA encounters a 2.5 m one; the Imazu section gives "
        "the scale of its cases, read from the runs.",
        "The papers give one figure per method and case, we judge over seeds and scenes.",
    ]
    functions = Counter((j.case, j.method) for j in results.select("functions")).values()
    if functions and IWSO_DWA_TABLE_1.runs:
        runs = "-".join(map(str, sorted({min(functions), max(functions)})))
        tested = sum(t.p is not None for v in verdicts if not v.variant for t in v.tests)
        few = (" too few to hold after Holm's correction" if tested and
               tested * smallest_p(min(functions)) >= judging.ALPHA else "")  # fmt: skip
        out.append(f"Benchmark functions: {runs} runs per function and algorithm against the "
                   f"paper's {IWSO_DWA_TABLE_1.runs}{',' if few else ''}{few}.")
    for v in verdicts:
        if v.verdict == judging.UNTESTABLE:
            out.append(f"{v.claim.id} is not testable: {v.reason}.")
    return out


def section(results: Results) -> Section:
    verdicts = [v for v in judging.paper_verdicts(results) if not v.variant]
    counts = Counter(v.verdict for v in verdicts)
    s = Section("summary", "Summary")
    s.paragraphs.append(compared(results))
    tally = ", ".join(f"{counts[k]} {k}" for k in judging.VERDICTS if counts[k])
    s.blocks.append(Table(
        "summary-verdicts", f"The papers' {len(verdicts)} claims for their own methods: {tally}",
        "The paper's figure (its method against its first rival); ours: the claim's own "
        "statistic of the method and the rival over the runs that measured it, the effect in "
        "the metric's units (method - rival) [95 % interval] and the relative change (> 0 "
        "better), the failed runs beside them; for several comparisons the one that decides; "
        "or the runs meeting an absolute claim [95 % interval]; the verdict after Holm's "
        "correction (the claims section gives the tests; docs/statistics.md the rules).",
        ["claim", "paper's figure", "ours", "verdict"],
        [[Cell(v.claim.id), Cell(claims.paper_figure(v.claim, named=False), "paper"),
          Cell(claims.headline(v)), Cell(v.verdict, claims.CSS[v.verdict])]
         for v in verdicts]))  # fmt: skip
    if yours := judging.user_verdicts(results):
        counts = Counter(v.verdict for v in yours)
        tally = ", ".join(f"{counts[k]} {k}" for k in judging.VERDICTS if counts[k])
        s.paragraphs.append(
            f"Your {len(yours)} claims (the pipelines' own, judged as the papers' are, in a "
            f"Holm family of their own; the section Your claims gives each): {tally}.")
        s.blocks.append(Table(
            "summary-your-verdicts", f"Your {len(yours)} claims: {tally}",
            "The claims of the pipelines behind these results, judged as the papers' are, "
            "with Holm's correction within their own family (the section Your claims gives "
            "the tests): ours as above and the verdict.",
            ["claim", "ours", "verdict"],
            [[Cell(v.claim.id), Cell(claims.headline(v)), Cell(v.verdict, claims.CSS[v.verdict])]
             for v in yours], placement=HTML))  # fmt: skip
    if line := against_baselines(results):
        s.paragraphs.append(line)
    s.paragraphs.append("Caveats. " + " ".join(caveats(results, verdicts)))
    return s


def against_baselines(results: Results) -> str:
    """One line: per scene family group where the field's baselines ran, each controller's
    comparisons with them better / worse of all, and how many equivalent when any
    (:func:`baselines.record`, the section's own standings); '' when no baseline ran."""
    found = baselines.standings(results)
    if not found:
        return ""
    parts = []
    for g in found:
        counted = [(s.method, baselines.record(s)) for s in g.standings]
        mine = ", ".join(f"{m} {w}/{lost} of {n}" + (f" ({same} equivalent)" if same else "")
                         for m, (w, lost, same, n) in counted if n)  # fmt: skip
        parts.append(f"{g.name}: {mine or 'too few paired runs'}")
    ran = [b for b in baselines.BASELINES if any(b in g.baselines for g in found)]
    return (f"Against the field's baselines ({' and '.join(ran)}; the section Against the "
            "field's baselines): each controller's comparisons with them, arrival time and "
            "closest distance paired by scene on the runs that measured them, better / worse "
            f"(uncorrected p < {judging.ALPHA}, a description; worse also when failing "
            f"significantly more often, exact McNemar) of all: {'; '.join(parts)}.")
