"""``policy``: a learned policy as a controller, so that a policy trained in the Gymnasium
environment (:mod:`usvtool.gym`, docs/gym.md) runs through ``usvtool simulate``, the pipelines
and the report as the papers' controllers do.

Each control period the policy gets the observation the environment gave it in training
(:class:`usvtool.sim.observation.Observer`, built from the own ship, the targets and the
encounter every controller gets), returns a velocity command, and the command is clipped into
what the vessel reaches in one period (:func:`usvtool.sim.observation.command`), as the
environment clips an action. NumPy only: no gymnasium, no learning library.

Its one parameter, ``policy``, names the policy:

- a ``.npz`` file of a feed-forward network (:class:`NetworkPolicy`, what
  ``examples/gym/train_linear.py`` writes): ``layout`` (the observation's layout as JSON),
  ``W0``, ``b0``, ``W1``, ``b1``, ... (``tanh`` between the layers; one layer is a linear
  policy); its two outputs through ``tanh`` are the speed, from ``min_speed`` (-1) to
  ``max_speed`` (1), and the yaw rate, ``output * max_yaw_rate``;
- ``module:callable``: a Python callable (an attribute path after the colon) taking the
  observation (a ``float32`` array) and returning ``(v, omega)`` in m/s and rad/s (positive
  to port); its observation is the default layout, or the one its attribute
  ``observation_layout`` gives (a :meth:`~usvtool.sim.observation.Layout.to_dict`);
- ``shipped`` (the default): the linear policy shipped beside this module,
  ``linear_policy.npz`` (examples/gym/train_linear.py's result; docs/gym.md says how it does).

A relative path is the current directory's; a batch's key holds the parameter's text, not the
file's content (a policy trained again under the same name does not rerun its jobs: name it
anew).

A policy that returns a non-finite command, or a callable that raises, ends the run as
``controller failed`` (:class:`~usvtool.sim.controllers.ControllerFailed`).
"""

from __future__ import annotations

import importlib
import json
import math
from pathlib import Path

import numpy as np

from usvtool.errors import UsvError
from usvtool.params import Param
from usvtool.sim.controllers.base import Controller, ControllerFailed, Decision
from usvtool.sim.observation import Layout, Observer, command

#: The policy ``policy: shipped`` runs: the linear policy examples/gym/train_linear.py trained.
SHIPPED = Path(__file__).with_name("linear_policy.npz")
SHIPPED_NAME = "shipped"


class NetworkPolicy:
    """A feed-forward network stored as ``.npz`` (the module docstring): ``policy(obs)`` is its
    two outputs in [-1, 1]; :meth:`command` maps them onto a vessel's limits."""

    def __init__(self, path: str | Path):
        path = Path(path)
        try:
            with np.load(path, allow_pickle=False) as data:
                arrays = {k: data[k] for k in data.files}
        except (OSError, ValueError) as exc:
            raise UsvError(f"{path}: not a policy .npz ({exc})") from None
        if "layout" not in arrays:
            raise UsvError(f"{path}: no 'layout' (the observation's layout as JSON)")
        try:
            self.layout = Layout.from_dict(json.loads(str(arrays["layout"])))
        except (ValueError, TypeError) as exc:
            raise UsvError(f"{path}: layout: {exc}") from None
        self.weights, self.biases = [], []
        width = self.layout.size
        for i in range(sum(k.startswith("W") for k in arrays)):
            w, b = arrays.get(f"W{i}"), arrays.get(f"b{i}")
            if w is None or b is None or w.ndim != 2 or w.shape[1] != width \
                    or b.shape != (w.shape[0],):  # fmt: skip
                raise UsvError(f"{path}: layer {i}: W{i} (n, {width}) and b{i} (n,) expected")
            if not (np.isfinite(w).all() and np.isfinite(b).all()):
                raise UsvError(f"{path}: layer {i}: non-finite weights")
            self.weights.append(np.asarray(w, float))
            self.biases.append(np.asarray(b, float))
            width = w.shape[0]
        if not self.weights or width != 2:
            raise UsvError(f"{path}: the last layer must have 2 outputs (speed, yaw rate)")

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        h = np.asarray(obs, float)
        last = len(self.weights) - 1
        for i, (w, b) in enumerate(zip(self.weights, self.biases, strict=True)):
            h = w @ h + b
            if i < last:
                h = np.tanh(h)
        return np.tanh(h)

    @staticmethod
    def command(vessel, out) -> tuple[float, float]:
        """The outputs ``out`` in [-1, 1] as (v, omega) within ``vessel``'s limits."""
        lo, hi = vessel.min_speed, vessel.max_speed
        return lo + (float(out[0]) + 1.0) * 0.5 * (hi - lo), float(out[1]) * vessel.max_yaw_rate


def load(spec: str):
    """``(policy, layout, network)``: the policy ``spec`` names (the module docstring), the
    observation layout it takes, and whether it is a network (its outputs in [-1, 1]) rather
    than a callable of (v, omega)."""
    if spec == SHIPPED_NAME:
        spec = str(SHIPPED)
    if spec.endswith(".npz") or Path(spec).is_file():
        if not Path(spec).is_file():
            raise UsvError(f"{spec}: no such file")
        network = NetworkPolicy(spec)
        return network, network.layout, True
    module, sep, attr = spec.partition(":")
    if not sep or not module or not attr:
        raise UsvError(f"{spec!r}: a policy is a .npz file or module:callable")
    try:
        obj = importlib.import_module(module)
        for part in attr.split("."):
            obj = getattr(obj, part)
    except Exception as exc:  # a policy's module may fail any way: one line
        raise UsvError(f"{spec}: cannot be loaded: {type(exc).__name__}: {exc}") from None
    if not callable(obj):
        raise UsvError(f"{spec}: not callable")
    layout = getattr(obj, "observation_layout", None)
    try:
        layout = Layout() if layout is None else Layout.from_dict(layout)
    except (ValueError, TypeError) as exc:
        raise UsvError(f"{spec}: observation_layout: {exc}") from None
    return obj, layout, False


class Policy(Controller):
    """A learned policy steering (the module docstring)."""

    name = "policy"
    parameters = {"policy": Param(SHIPPED_NAME, "the policy: a .npz network, module:callable, "
                                  "or shipped (the linear policy usvtool ships)")}

    def __init__(self, **params):
        super().__init__(**params)
        self.policy, self.layout, self.network = load(self.params["policy"])
        self.observer: Observer | None = None

    def reset(self, world) -> None:
        super().reset(world)
        self.observer = Observer(world, self.layout)

    def decide(self, own, targets, encounter=None) -> Decision:
        obs = self.observer(own, targets, encounter)
        vessel = self.world.vessel
        try:
            out = self.policy(obs)
            v, omega = NetworkPolicy.command(vessel, out) if self.network else out
            v, omega = float(v), float(omega)
        except Exception as exc:  # the user's callable may fail any way: the run's failure
            raise ControllerFailed(f"the policy failed: {type(exc).__name__}: {exc}") from None
        if not (math.isfinite(v) and math.isfinite(omega)):
            raise ControllerFailed(f"the policy returned ({v}, {omega}), not finite")
        return Decision(*command(vessel, own, self.world.period, v, omega))
