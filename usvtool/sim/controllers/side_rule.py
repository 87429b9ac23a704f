"""The side rule of a controller: the side the most urgent encounter asks for, and what the
controller does with it.

The side comes from a table of :mod:`usvtool.sim.sides` (the ``sides`` parameter; ``none``: no
rule). A controller that *removes* (CCDWA) drops the samples turning the other way from its
candidates; one that *prefers* (UDWA, gdwa: ``priority`` > 0) multiplies the preferred side's
scores by ``1 + priority``, with ``safe`` (``safe_priority``) only those whose clearance reaches
``cap`` (``dist_max``). The events it explains itself with: ``side-rule-overridden`` when the
safety invariant takes the removed side after all, ``rule2-departure`` when a step turns away
from the preferred side.
"""

from __future__ import annotations

import functools

import numpy as np

from usvtool.sim import sides as side_rules


@functools.cache
def _kernels():
    """:mod:`usvtool.sim.rollout_kernels`, imported at the first call (numba's import: a run's,
    not the command line's) and then at the cost of a cached call, not an import's
    microseconds, every step."""
    from usvtool.sim import rollout_kernels

    return rollout_kernels


class SideRule:
    """The side rule (see the module docstring)."""

    def __init__(self, table: str, removes: bool, priority: float, safe: bool, cap: float):
        self.table, self.removes, self.priority, self.safe, self.cap = (
            table, removes, priority, safe, cap
        )  # fmt: skip

    def side(self, encounter) -> int:
        """The side the table asks for in ``encounter``
        (:class:`~usvtool.sim.controllers.base.Encounter` or None)."""
        if encounter is None or self.table == "none":
            return side_rules.EITHER
        return side_rules.side_for(self.table, encounter.cls)

    def removed(self, side: int, omega: np.ndarray) -> np.ndarray:
        """(N,) bool: the samples the rule removes (those turning away from ``side``)."""
        if side != side_rules.EITHER and self.removes:
            return np.sign(omega) == -side
        return np.zeros(omega.size, bool)

    def favour(self, side: int, r, score: np.ndarray) -> np.ndarray:
        """``score`` with the preferred side's bonus."""
        if side == side_rules.EITHER or not self.priority > 0:
            return score
        # the side's samples (with safe: only where no target or shore comes near) times
        # 1 + priority, compiled
        return _kernels().favour(score, r.omega, int(side), float(1 + self.priority),
                                 r.clearance, float(self.cap), bool(self.safe))  # fmt: skip

    @staticmethod
    def overridden(side: int, horizon: float) -> dict:
        """The event of a step whose candidates are the removed side's after all."""
        return {
            "kind": "side-rule-overridden",
            "preferred": side_rules.NAMES[side],
            "reason": f"every {side_rules.NAMES[side]} sample meets a contact within {horizon:g} s",
        }

    @staticmethod
    def departure(encounter, side: int, r, score: np.ndarray, free: np.ndarray) -> dict:
        """A Rule 2 departure: the step turned away from the side the rule prefers."""
        own_side = np.sign(r.omega) == side
        if not (own_side & free).any():
            reason = f"every {side_rules.NAMES[side]} sample meets a contact within the horizon"
        else:
            best_own = float(np.max(np.where(own_side, score, -np.inf)))
            reason = (
                f"best {side_rules.NAMES[side]} score {best_own:.4g} below "
                f"{float(np.max(score)):.4g} on the other side"
            )
        return {
            "kind": "rule2-departure",
            "target": encounter.target,
            "class": encounter.cls,
            "preferred": side_rules.NAMES[side],
            "reason": reason,
        }
