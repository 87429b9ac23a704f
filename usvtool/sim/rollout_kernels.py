"""Compiled kernels of the controllers' rollouts (:mod:`usvtool.sim.controllers`), with numba.

One control step rolls some 460 velocity samples out over 30-50 horizon points and checks every
point against the grid's clearance field and every target: those loops over (horizon point,
sample) run here, with no (horizon, samples) temporaries, and so does the whole of a period
window's fan (:func:`arc_fan`: its directions, running sums and chords) and of a horizon
window's ramps (:func:`horizon_sweep`; :func:`usvtool.sim.vessel.ramps` is their NumPy
definition). Each kernel
repeats the NumPy expressions it stands for operation by operation (the same products, sums and
comparisons in the same order, and no fused multiply-add: numba contracts none without
``fastmath``), so positions, contacts and clearances are the same bits as NumPy's
(tests/sim/test_rollout_kernels.py compares them). The inner loops run over samples in
contiguous memory, branch-free where it counts, so that LLVM vectorises them.

The rest of a step's array work on its few hundred samples runs here too, where NumPy's
dispatch cost more than the work (a microsecond or more a call): the window's axes and pairs
(:func:`window_axes`), the candidates (:func:`candidates`), the critics' sum
(:func:`weighted_shares`: NumPy's pairwise sums are left to NumPy), the heading rewards and the
side bonus; and ``vo``'s candidates and velocity obstacles (:func:`vo_candidates`,
:func:`vo_contacts`, :func:`vo_near`). Their ``sqrt`` (correctly rounded) and ``hypot`` (the C
library's in both) give NumPy's bits (tests/sim/test_step_kernels.py); ``arctan2``, ``sin`` and
``cos`` of arrays stay NumPy's, whose SIMD loops need not give the C library's bits. ``VEL_EPS``
(:mod:`usvtool.encounter`) is compiled in as a constant: after changing it, touch this file
(numba's cache keys a kernel on this file only).

Layout: positions ``x``, ``y`` are ``(T, N)``, time-major, sample ``n = i·R + k`` the speed ``i``
and the yaw rate ``k`` of the window's grid (:class:`usvtool.sim.vessel.Fan`).

Each kernel has its signature (:func:`usvtool.lazy_kernels.declared`), compiled, or loaded
from numba's cache in ``__pycache__``, at the kernel's first call, not at import: a run loads
the kernels it calls and no others (loading all 37 of these modules' at import cost some 0.55 s
of CPU a process). The
ufuncs :func:`toward` and :func:`travelled` are made at their first use (the module's
``__getattr__``). Imported lazily, by :mod:`usvtool.sim.vessel` when it rolls a fan out, so that
reading a scenario or building the command line does not import numba.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, vectorize
from numba import types as nt

from usvtool.encounter import VEL_EPS
from usvtool.lazy_kernels import declared
from usvtool.sim.vessel import SINC_ZERO, ZERO_TOLERANCE

_B, _F, _I, _C = nt.boolean, nt.float64, nt.int64, nt.complex128
_ROWS = _F[:, ::1]  # a C-ordered 2-D array: (T, N), (V, R), (T, V), (k, 2)
_TURNS = _C[:, ::1]  # (T, R) complex: a direction or a sum of them per time and yaw rate
_OPTIONS = {"cache": True, "nogil": True}


#: Relative margin of the distance bounds that skip work: a bound within it of its limit is not
#: trusted and the work is done (the round-off in a bound is some 1e-15 of it).
MARGIN = 1e-6


@declared(_F[::1](_F, _F, _I, _F[::1], _F), **_OPTIONS)
def axis(lo, hi, n, extra, tolerance) -> np.ndarray:
    """:func:`usvtool.sim.vessel._axis` (its definition): ``n`` values from ``lo`` to ``hi`` as
    ``np.linspace`` makes them (``i`` times the step plus ``lo``, ``i / (n - 1)`` times the
    width when the step underflows to zero, ``hi`` last), and the ``extra`` ones between them,
    those within ``tolerance`` of zero made zero, sorted, without repeats."""
    if lo == hi:
        return np.full(1, lo)
    step = (hi - lo) / (n - 1)
    values = np.empty(n + extra.size)
    for i in range(n - 1):
        values[i] = i * step + lo if step else i / (n - 1) * (hi - lo) + lo
    values[n - 1] = hi
    count = n
    for e in extra:
        if lo <= e <= hi:
            values[count] = e
            count += 1
    for i in range(count):
        if abs(values[i]) <= tolerance:
            values[i] = 0.0
    # sorted by insertion (the extras into the sorted values), repeats dropped as they come:
    # what np.sort and a mask give (no NaN, no -0.0 is left), without compiling numba's
    # quicksort and boolean indexing (1.5-2 s of a fresh clone's compile)
    kept = 0
    for i in range(count):
        value = values[i]
        at = kept
        while at > 0 and values[at - 1] > value:
            at -= 1
        if at > 0 and values[at - 1] == value:
            continue
        for j in range(kept, at, -1):
            values[j] = values[j - 1]
        values[at] = value
        kept += 1
    return values[:kept].copy()


_AXES = nt.Tuple((_F[::1], _F[::1], _F[::1], _F[::1]))


@declared(_AXES(_F, _F, _F[::1], _F, _I, _I), **_OPTIONS)
def window_axes(v, omega, limits, span, n_v, n_omega):
    """The samples of a step: :func:`usvtool.sim.vessel.window` of the velocity ``(v, omega)``
    over ``span`` (eqs. 18-19; ``limits``: the vessel's ``min_speed``, ``max_speed``,
    ``max_decel``, ``max_accel``, ``max_yaw_rate``, ``max_yaw_accel``), its axes as
    :func:`usvtool.sim.vessel.samples` makes them with ``current=(v, omega)``, and the pairs,
    the speed varying slowest (``np.repeat`` and ``np.tile``): ``(speeds, rates, v, omega)``.
    The window's clips are ``min(max(limit, lo), hi)`` in floats, as there."""
    min_speed, max_speed, max_decel, max_accel, max_yaw_rate, max_yaw_accel = limits
    v_down, v_up = v - max_decel * span, v + max_accel * span
    w_down, w_up = omega - max_yaw_accel * span, omega + max_yaw_accel * span
    v_lo, v_hi = min(max(min_speed, v_down), v_up), min(max(max_speed, v_down), v_up)
    w_lo, w_hi = min(max(-max_yaw_rate, w_down), w_up), min(max(max_yaw_rate, w_down), w_up)
    speeds = axis(v_lo, v_hi, n_v, np.full(1, v), ZERO_TOLERANCE * (v_hi - v_lo))
    extra = np.empty(2)
    extra[0], extra[1] = 0.0, omega
    rates = axis(w_lo, w_hi, n_omega, extra, ZERO_TOLERANCE * (w_hi - w_lo))
    n = speeds.size * rates.size
    pair_v, pair_omega = np.empty(n), np.empty(n)
    for i in range(speeds.size):
        for k in range(rates.size):
            pair_v[i * rates.size + k] = speeds[i]
            pair_omega[i * rates.size + k] = rates[k]
    return speeds, rates, pair_v, pair_omega


@declared(_F(_F, _F, _F, _F, _F), **_OPTIONS)
def toward_one(now, target, down, up, t) -> float:
    """:func:`usvtool.sim.vessel.toward` (its definition) of one value."""
    return now + min(max(target - now, -down * t), up * t)


def toward(now, target, down, up, t):
    """:func:`toward_one` as a ufunc: one compiled pass where the NumPy expression made five
    arrays."""
    return toward_one(now, target, down, up, t)


@declared(_F(_F, _F, _F, _F, _F), **_OPTIONS)
def travelled_one(now, target, down, up, t) -> float:
    """:func:`usvtool.sim.vessel.travelled` (its definition) of one value."""
    change = target - now
    rate = up if up == down or change > 0 else down
    ramp = min(t, abs(change) / rate)
    return now * t + change * (t - ramp) + math.copysign(rate / 2 * ramp * ramp, change)


def travelled(now, target, down, up, t):
    """:func:`travelled_one` as a ufunc."""
    return travelled_one(now, target, down, up, t)


#: The ufuncs' Python functions, made ufuncs (``vectorize`` of their one signature: compiled
#: there) at their first use by :func:`__getattr__`.
_UFUNCS = {f.__name__: f for f in (toward, travelled)}
del toward, travelled


def __getattr__(name: str):
    """:func:`toward` or :func:`travelled`, made at the first use."""
    if name not in _UFUNCS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    ufunc = globals()[name] = vectorize([_F(_F, _F, _F, _F, _F)], cache=True)(_UFUNCS[name])
    return ufunc


@njit(inline="always")
def _arc_row(t, x0, y0, chord, summed, x, y, sum_x, sum_y) -> None:
    """Row ``t`` of :func:`arc_points`' ``x`` and ``y`` (``sum_x``, ``sum_y``: its scratch)."""
    speeds, rates = chord.shape
    for k in range(rates):
        sum_x[k], sum_y[k] = summed[t, k].real, summed[t, k].imag
    for i in range(speeds):
        base = i * rates
        for k in range(rates):
            x[t, base + k] = chord[i, k] * sum_x[k] + x0
    for i in range(speeds):
        base = i * rates
        for k in range(rates):
            y[t, base + k] = chord[i, k] * sum_y[k] + y0


@declared(_F[::1](_F, _F, _ROWS, _TURNS, _ROWS, _ROWS), **_OPTIONS)
def arc_points(x0, y0, chord, summed, x, y) -> np.ndarray:
    """The arcs' positions (:func:`usvtool.sim.vessel.arcs`): ``x[t, i·R + k] = chord[i, k] ·
    summed[t, k].real + x0`` (and ``y`` with the imaginary part), ``chord`` ``(V, R)`` the chord
    lengths (>= 0), ``summed`` ``(T, R)`` the summed unit chords; written into ``x`` and ``y``.
    Returns a bound on the distance of every point from ``(x0, y0)`` at each time ``(T,)``: the
    longest chord of each rate times the length of its summed chords."""
    steps, rates = summed.shape
    speeds = chord.shape[0]
    sum_x, sum_y = np.empty(rates), np.empty(rates)
    for t in range(steps):
        _arc_row(t, x0, y0, chord, summed, x, y, sum_x, sum_y)
    longest = np.zeros(rates)
    for i in range(speeds):
        for k in range(rates):
            longest[k] = max(longest[k], chord[i, k])
    radius = np.zeros(steps)
    for t in range(steps):
        far = 0.0
        for k in range(rates):
            far = max(far, longest[k] ** 2 * (summed[t, k].real ** 2 + summed[t, k].imag ** 2))
        radius[t] = math.sqrt(far)
    return radius


@declared(nt.Tuple((_ROWS, _TURNS))(_F, _F[::1], _F[::1], _F, _TURNS), **_OPTIONS)
def arc_chords(psi0, speeds, rates, dt, u) -> tuple[np.ndarray, np.ndarray]:
    """The first part of :func:`arc_fan` (its definition): the directions ``u`` (written), the
    chords ``(V, R)`` and the summed unit chords ``(T, R)``, what :func:`arc_points` takes."""
    steps, rates_n = u.shape
    speeds_n = speeds.size
    chord = np.empty((speeds_n, rates_n))
    summed = np.empty((steps, rates_n), np.complex128)
    for k in range(rates_n):
        turn = rates[k] * dt
        start = psi0 + turn / 2
        re, im = math.cos(start), math.sin(start)
        c, s = math.cos(turn), math.sin(turn)
        u[0, k] = complex(re, im)
        sum_re, sum_im = re, im
        summed[0, k] = complex(sum_re, sum_im)
        for t in range(1, steps):
            re, im = re * c - im * s, re * s + im * c
            u[t, k] = complex(re, im)
            sum_re, sum_im = sum_re + re, sum_im + im
            summed[t, k] = complex(sum_re, sum_im)
        arg = math.pi * (turn / (2 * math.pi))
        if arg == 0.0:
            arg = SINC_ZERO
        sinc = math.sin(arg) / arg
        for i in range(speeds_n):
            chord[i, k] = speeds[i] * dt * sinc
    return chord, summed


@declared(_F[::1](_F, _F, _F, _F[::1], _F[::1], _F, _TURNS, _ROWS, _ROWS), **_OPTIONS)
def arc_fan(x0, y0, psi0, speeds, rates, dt, u, x, y) -> np.ndarray:
    """The whole of :func:`usvtool.sim.vessel.arcs`: each yaw rate's unit chord directions
    ``u[t, k]`` (written: ``exp(i (psi0 + turn / 2))``, then each period's times ``exp(i
    turn)``, ``turn = rates[k] dt``), their running sums, the chords ``speeds[i] dt
    sinc(turn / 2 pi)`` (``np.sinc``: ``sin(y) / y`` of ``y = pi t``, its epsilon for 0)
    (:func:`arc_chords`) and, by :func:`arc_points`, the positions ``x``, ``y`` (written) and
    their distance bound.

    The running product is the textbook complex product in real arithmetic, ``(a c - b s, a s
    + b c)``, with no fused multiply-add: the same bits on every CPU (NumPy's complex multiply
    fuses on some, as AVX-512's, so its running product differs there in the last bit); the
    exponentials are ``cos`` and ``sin``, as NumPy's ``exp`` of an imaginary number gives them.
    """
    chord, summed = arc_chords(psi0, speeds, rates, dt, u)
    return arc_points(x0, y0, chord, summed, x, y)


_NEAREST = (_I[::1], _F[::1], _C[::1])  # closest's: the row, the squared distance, the point


@declared(nt.Tuple((_F[::1], *_NEAREST))(_F, _F, _ROWS, _TURNS, _ROWS, _ROWS, _F, _F), **_OPTIONS)
def arc_points_closest(x0, y0, chord, summed, x, y, px, py):
    """:func:`arc_points` and :func:`closest` to ``(px, py)`` of the points it writes, each
    row's distances taken as soon as the row is made (while it is in cache; the rows in the
    same order): ``(radius, row, to_point, point)``."""
    steps, rates = summed.shape
    speeds = chord.shape[0]
    n = speeds * rates
    sum_x, sum_y = np.empty(rates), np.empty(rates)
    row = np.zeros(n, np.int64)
    best = np.full(n, np.inf)
    for t in range(steps):
        _arc_row(t, x0, y0, chord, summed, x, y, sum_x, sum_y)
        for s in range(n):  # closest's, on the row just made (in cache)
            dx, dy = x[t, s] - px, y[t, s] - py
            d2 = dx * dx + dy * dy
            closer = d2 < best[s]
            best[s] = d2 if closer else best[s]
            row[s] = t if closer else row[s]
    longest = np.zeros(rates)
    for i in range(speeds):
        for k in range(rates):
            longest[k] = max(longest[k], chord[i, k])
    radius = np.zeros(steps)
    for t in range(steps):
        far = 0.0
        for k in range(rates):
            far = max(far, longest[k] ** 2 * (summed[t, k].real ** 2 + summed[t, k].imag ** 2))
        radius[t] = math.sqrt(far)
    point = np.empty(n, np.complex128)
    for s in range(n):
        point[s] = complex(x[row[s], s], y[row[s], s])
    return radius, row, best, point


@declared(_F[::1](_F, _F, _ROWS, _TURNS, _ROWS, _ROWS), **_OPTIONS)
def ramp_points(x0, y0, chord, u, x, y) -> np.ndarray:
    """The ramps' positions (:func:`usvtool.sim.vessel.ramps`): the running sums over the periods
    of ``chord[t, i] · u[t, k].real`` (and the imaginary part) plus the start, ``chord`` ``(T,
    V)`` each period's chord length per speed (>= 0), ``u`` ``(T, R)`` its direction per yaw
    rate; written into ``x`` and ``y``. Returns a bound on the distance of every point from
    ``(x0, y0)`` at each time: the longest distance run."""
    steps, rates = u.shape
    speeds = chord.shape[1]
    u_x, u_y = np.empty(rates), np.empty(rates)
    sx = np.empty(speeds * rates)
    sy = np.empty(speeds * rates)
    for t in range(steps):
        for k in range(rates):
            u_x[k], u_y[k] = u[t, k].real, u[t, k].imag
        for i in range(speeds):  # as np.cumsum: the first term, then each sum; x and y at once
            base, c = i * rates, chord[t, i]
            if t == 0:
                for k in range(rates):
                    sx[base + k] = c * u_x[k]
                    sy[base + k] = c * u_y[k]
            else:
                for k in range(rates):
                    sx[base + k] += c * u_x[k]
                    sy[base + k] += c * u_y[k]
            for k in range(rates):
                x[t, base + k] = sx[base + k] + x0
                y[t, base + k] = sy[base + k] + y0
    run = np.zeros(speeds)
    radius = np.zeros(steps)
    for t in range(steps):
        for i in range(speeds):
            run[i] += chord[t, i]
        radius[t] = run.max()
    return radius


@declared(_I(_F, _F, _I, _I, _F, _F, _F), inline="always", **_OPTIONS)
def _cell_index(x, y, width, height, left, top, scale) -> int:
    """The index of the point's cell in :attr:`usvtool.clearance.Clearance.padded`, the field of
    ``width`` x ``height`` cells with a zero border (:meth:`usvtool.clearance.Clearance.at`)."""
    col = min(max((x - left) * scale + 1, 0.0), width + 1.0)
    row = min(max((top - y) * scale + 1, 0.0), height + 1.0)
    return int(row) * (width + 2) + int(col)


_ROW = (_F[::1], _F[::1], _F, _F, _F[::1], _F[::1], _F, _F, _B[::1])


@declared(_B(*_ROW), inline="always", **_OPTIONS)
def _domain_fast(x, y, tx, ty, u_x, u_y, along, across, intrudes) -> bool:
    """The domain test of one row (:func:`usvtool.encounter.domain_ellipse`, into ``intrudes``)
    with the divisions by the semi-axes as multiplications by their reciprocals, which vectorise:
    marks the points whose form lies below ``1 - 1e-9`` (a few ulps off the exact form: surely
    inside) and returns whether some point's lies within 1e-9 of 1 (:func:`_domain_exact`
    decides those)."""
    rates = u_x.shape[0]
    to_along, to_across = 1.0 / along, 1.0 / across
    unsure = 0
    for i in range(x.shape[0] // rates):
        base = i * rates
        for k in range(rates):
            dx, dy = tx - x[base + k], ty - y[base + k]
            a = (dx * u_x[k] + dy * u_y[k]) * to_along
            c = (dx * u_y[k] - dy * u_x[k]) * to_across
            form = a * a + c * c
            intrudes[base + k] |= form <= 1 - 1e-9
            unsure += abs(form - 1) <= 1e-9
    return unsure > 0


@declared(nt.void(*_ROW), inline="always", **_OPTIONS)
def _domain_exact(x, y, tx, ty, u_x, u_y, along, across, intrudes) -> None:
    """The domain test of one row as :func:`usvtool.encounter.domain_ellipse` computes it."""
    rates = u_x.shape[0]
    for i in range(x.shape[0] // rates):
        base = i * rates
        for k in range(rates):
            dx, dy = tx - x[base + k], ty - y[base + k]
            a = (dx * u_x[k] + dy * u_y[k]) / along
            c = (dx * u_y[k] - dy * u_x[k]) / across
            intrudes[base + k] |= a * a + c * c <= 1


@declared(_F(_F, _F, _F, _F, _F, _F, _F, _F), inline="always", **_OPTIONS)
def _segment_distance(px, py, vx, vy, t0, t1, x0, y0) -> float:
    """The distance from ``(x0, y0)`` to the track ``(px, py) + (vx, vy) · t``, ``t0 <= t <=
    t1``."""
    ax, ay = px + vx * t0 - x0, py + vy * t0 - y0
    dx, dy = vx * (t1 - t0), vy * (t1 - t0)
    length2 = dx * dx + dy * dy
    f = min(max(-(ax * dx + ay * dy) / length2, 0.0), 1.0) if length2 > 0 else 0.0
    return math.hypot(ax + f * dx, ay + f * dy)


_CONTACTS = nt.Tuple((_F[::1], _B[::1], _F[::1], _B[::1]))


@declared(_CONTACTS(_ROWS, _ROWS, _F[::1], _TURNS, _F[::1], _F, _F,  # the fan, times, start
                _ROWS, _ROWS, _F[::1],  # the targets: positions, velocities, lengths
                _F[::1], _I, _F, _F, _F, _F,  # the padded field, its width, left, top, scale, cell
                _F, _I, _F, _F, _F, _F),  # own length, the domain's rows, axes, reach; the cap
      **_OPTIONS)  # fmt: skip
def contacts(x, y, radius, u, times, x0, y0, pos, vel, length, padded, width, left, top, scale,
             cell, own_length, every, along, across, trigger, cap):  # fmt: skip
    """The checks of :meth:`usvtool.sim.controllers.base.DynamicWindow.rollouts`, per sample:
    ``(contact, static_first, clearance, intrudes)``.

    - the grid (``padded`` and ``width``: :attr:`usvtool.clearance.Clearance.padded`, an empty
      array on open water): a point's clearance is its cell's, 0 outside the grid; a contact
      where it is at most the own ship's radius (``own_length / 2``);
    - the targets at ``pos + vel · t`` (``(k, 2)``, ``length`` ``(k,)``): a contact where the
      centres come within half the sum of the two lengths; the domain test (``every`` > 0: at
      the rows ``0, every, 2·every, ...``) when the target comes within ``sqrt(trigger)`` of some
      point: inside the ellipse of semi-axes ``along`` and ``across`` along the period's
      direction ``u[t, k]`` (complex, ``(T, R)``: :func:`usvtool.encounter.domain_ellipse`);
    - ``contact``: the first time of either, ``inf`` without; ``static_first``: the first
      contact is with the grid; ``clearance``: the smallest gap to the grid or a target over the
      horizon; ``intrudes``: some target enters the domain.

    Work that cannot matter is skipped by distance bounds (``radius``: how far any rollout is
    from the start at each time): a target whose track over the horizon stays farther from the
    start than that spread plus ``far`` (the larger of half the sum of the lengths plus ``cap``
    and ``sqrt(trigger)``), and for the others each such row; the grid's rows where the start's
    clearance less the spread and two cells (the field is a distance transform of cell centres,
    1-Lipschitz up to a cell's diagonal) leaves more than ``cap``. So ``clearance`` is exact
    where below ``cap`` and at least ``cap`` elsewhere, and the rest is exact.
    """
    steps, n = x.shape
    rates = u.shape[1]
    half = own_length / 2
    static_at = np.full(n, steps)  # the first row of a contact with the grid; steps: none
    clearance = np.full(n, np.inf)
    spread = radius.max()
    if padded.size > 0:
        height = padded.size // (width + 2) - 2
        start = padded[_cell_index(x0, y0, width, height, left, top, scale)]
        cells = np.empty(n, np.int64)
        for t in range(steps):
            if start - radius[t] - 2 * cell - half > cap * (1 + MARGIN) + MARGIN:
                continue  # every point of the row is farther than the cap from the grid
            for s in range(n):  # apart from the lookups: this loop vectorises, they do not
                cells[s] = _cell_index(x[t, s], y[t, s], width, height, left, top, scale)
            for s in range(n):
                gap = padded[cells[s]] - half
                clearance[s] = min(clearance[s], gap)
                static_at[s] = min(static_at[s], t if gap <= 0 else steps)
    contact_at = static_at.copy()  # the first row of any contact
    intrudes = np.zeros(n, np.bool_)
    closest2 = np.empty(n)
    active = np.empty(steps, np.bool_)
    nearby = np.empty(steps, np.int64)
    u_x, u_y = np.empty(rates), np.empty(rates)
    for j in range(pos.shape[0]):
        reach = (own_length + length[j]) / 2
        reach2 = reach * reach
        far = max(reach + cap, math.sqrt(trigger)) * (1 + MARGIN) + MARGIN
        px, py, vx, vy = pos[j, 0], pos[j, 1], vel[j, 0], vel[j, 1]
        if _segment_distance(px, py, vx, vy, times[0], times[-1], x0, y0) > far + spread:
            continue  # her whole track over the horizon
        rows = 0
        for t in range(steps):
            dx, dy = px + vx * times[t] - x0, py + vy * times[t] - y0
            active[t] = dx * dx + dy * dy <= (far + radius[t]) ** 2
            rows += active[t]
        if rows == 0:
            continue
        closest2[:] = np.inf
        for t in range(steps):
            near = 0  # the row's points within the domain's reach of her
            if active[t]:
                tx, ty = px + vx * times[t], py + vy * times[t]
                for s in range(n):
                    dx, dy = tx - x[t, s], ty - y[t, s]
                    d2 = dx * dx + dy * dy
                    closest2[s] = min(closest2[s], d2)
                    contact_at[s] = min(contact_at[s], t if d2 <= reach2 else steps)
                    near += d2 <= trigger
            nearby[t] = near
        for s in range(n):
            clearance[s] = min(clearance[s], math.sqrt(closest2[s]) - reach)
        if every > 0 and nearby.any():
            for t in range(0, steps, every):
                if nearby[t]:
                    tx, ty = px + vx * times[t], py + vy * times[t]
                    for k in range(rates):
                        u_x[k], u_y[k] = u[t, k].real, u[t, k].imag
                    if _domain_fast(x[t], y[t], tx, ty, u_x, u_y, along, across, intrudes):
                        _domain_exact(x[t], y[t], tx, ty, u_x, u_y, along, across, intrudes)
    contact = np.full(n, np.inf)
    static_first = np.zeros(n, np.bool_)
    for s in range(n):
        if contact_at[s] < steps:
            contact[s] = times[contact_at[s]]
            static_first[s] = static_at[s] == contact_at[s]
    return contact, static_first, clearance, intrudes


@declared(nt.Tuple((_I[::1], _F[::1], _C[::1]))(_ROWS, _ROWS, _F, _F), **_OPTIONS)
def closest(x, y, px, py) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each rollout's point closest to ``(px, py)``: its row (the first of equals), its squared
    distance and the point ``x + iy``, ``(N,)`` each."""
    steps, n = x.shape
    row = np.zeros(n, np.int64)
    best = np.full(n, np.inf)
    for t in range(steps):
        for s in range(n):
            dx, dy = x[t, s] - px, y[t, s] - py
            d2 = dx * dx + dy * dy
            closer = d2 < best[s]
            best[s] = d2 if closer else best[s]
            row[s] = t if closer else row[s]
    point = np.empty(n, np.complex128)
    for s in range(n):
        point[s] = complex(x[row[s], s], y[row[s], s])
    return row, best, point


#: The checks' constants of a run, after the targets (:func:`contacts`: the padded field, its
#: width, left, top, scale and cell; the own length, the domain's rows, axes and reach; the cap).
_CHECKS = (_F[::1], _I, _F, _F, _F, _F, _F, _I, _F, _F, _F, _F)
#: What :func:`sweep` finds per sample: :func:`contacts`' four, then :func:`closest`'s three.
_FOUND = (_F[::1], _B[::1], _F[::1], _B[::1], _I[::1], _F[::1], _C[::1])


@declared(nt.Tuple(_FOUND)(_ROWS, _ROWS, _F[::1], _TURNS, _F[::1], _F, _F, _ROWS, _ROWS, _F[::1],
                       *_CHECKS, _F, _F), **_OPTIONS)  # fmt: skip
def sweep(x, y, radius, u, times, x0, y0, pos, vel, length, padded, width, left, top, scale,
          cell, own_length, every, along, across, trigger, cap, gx, gy):  # fmt: skip
    """The checks of a step's rollouts in one call: :func:`contacts` (its arguments), then
    :func:`closest` to the goal ``(gx, gy)``: ``(contact, static_first, clearance, intrudes,
    row, to_goal, near)``."""
    contact, static_first, clearance, intrudes = contacts(
        x, y, radius, u, times, x0, y0, pos, vel, length, padded, width, left, top, scale, cell,
        own_length, every, along, across, trigger, cap)  # fmt: skip
    row, to_goal, near = closest(x, y, gx, gy)
    return contact, static_first, clearance, intrudes, row, to_goal, near


#: A window's whole step (:func:`period_sweep`, :func:`horizon_sweep`): the own ship, the
#: window, the times, the targets, the checks and the goal; the samples, their points and what
#: :func:`sweep` finds.
_STEP = nt.Tuple((_F[::1], _F[::1], _ROWS, _ROWS, *_FOUND))(
    _F, _F, _F, _F, _F, _F[::1], _F, _I, _I, _F[::1], _ROWS, _ROWS, _F[::1], *_CHECKS, _F, _F)


@declared(_STEP, **_OPTIONS)
def period_sweep(x0, y0, psi0, v0, omega0, limits, span, n_v, n_omega, times, pos, vel, length,
                 padded, width, left, top, scale, cell, own_length, every, along, across,
                 trigger, cap, gx, gy):  # fmt: skip
    """A period window's whole step of rollouts in one call
    (:meth:`usvtool.sim.controllers.windows.PeriodWindow.sweep`): :func:`window_axes` of the
    own ship's velocity ``(v0, omega0)``, their fan from ``(x0, y0, psi0)`` at the ``times``
    (:func:`arc_fan`, its step the first time, with the points closest to the goal as they are
    made: :func:`arc_points_closest`) and :func:`contacts` of it, what :func:`sweep` gives:
    ``(v, omega, x, y, contact, static_first, clearance, intrudes, row, to_goal, near)``."""
    speeds, rates, v, omega = window_axes(v0, omega0, limits, span, n_v, n_omega)
    steps = times.size
    u = np.empty((steps, rates.size), np.complex128)
    x, y = np.empty((steps, v.size)), np.empty((steps, v.size))
    chord, summed = arc_chords(psi0, speeds, rates, times[0], u)
    radius, row, to_goal, near = arc_points_closest(x0, y0, chord, summed, x, y, gx, gy)
    contact, static_first, clearance, intrudes = contacts(
        x, y, radius, u, times, x0, y0, pos, vel, length, padded, width, left, top, scale, cell,
        own_length, every, along, across, trigger, cap)  # fmt: skip
    return v, omega, x, y, contact, static_first, clearance, intrudes, row, to_goal, near


@declared(_STEP, **_OPTIONS)
def horizon_sweep(x0, y0, psi0, v0, omega0, limits, span, n_v, n_omega, times, pos, vel, length,
                  padded, width, left, top, scale, cell, own_length, every, along, across,
                  trigger, cap, gx, gy):  # fmt: skip
    """A horizon window's whole step of rollouts in one call
    (:meth:`usvtool.sim.controllers.windows.HorizonWindow.sweep`), :func:`period_sweep`'s
    arguments and results: :func:`window_axes`, the ramps of
    :func:`usvtool.sim.vessel.ramps` from ``(x0, y0, psi0)`` at the ``times`` (each period's
    chord ``dt · toward`` per speed and direction ``exp(i (psi0 + travelled))`` per yaw rate at
    its middle ``dt (j + 1/2)``, ``dt`` the first time; the exponential's ``cos`` and ``sin``,
    as NumPy's ``exp`` of an imaginary number gives them, :func:`arc_fan`), their points
    (:func:`ramp_points`) and :func:`sweep` of them."""
    speeds, rates, v, omega = window_axes(v0, omega0, limits, span, n_v, n_omega)
    decel, accel, yaw = limits[2], limits[3], limits[5]
    steps, dt = times.size, times[0]
    chord = np.empty((steps, speeds.size))
    u = np.empty((steps, rates.size), np.complex128)
    for t in range(steps):
        mid = dt * (t + 0.5)
        for i in range(speeds.size):
            chord[t, i] = dt * toward_one(v0, speeds[i], decel, accel, mid)
        for k in range(rates.size):
            heading = psi0 + travelled_one(omega0, rates[k], yaw, yaw, mid)
            u[t, k] = complex(math.cos(heading), math.sin(heading))
    x, y = np.empty((steps, v.size)), np.empty((steps, v.size))
    radius = ramp_points(x0, y0, chord, u, x, y)
    contact, static_first, clearance, intrudes, row, to_goal, near = sweep(
        x, y, radius, u, times, x0, y0, pos, vel, length, padded, width, left, top, scale, cell,
        own_length, every, along, across, trigger, cap, gx, gy)  # fmt: skip
    return v, omega, x, y, contact, static_first, clearance, intrudes, row, to_goal, near


@declared(_B[::1](_ROWS, _ROWS, _F[::1], _F, _F, _F, _F, _F, _F, _F), **_OPTIONS)
def crosses_ahead(x, y, times, px, py, vx, vy, hx, hy, now) -> np.ndarray:
    """Whether each rollout crosses the course line of a target at ``(px, py)`` moving at
    ``(vx, vy)`` (unit direction ``(hx, hy)``) ahead of her: at some time the side of her line
    it is on (the sign of ``hx·ry - hy·rx``, ``r`` the offset from the target) differs from
    ``now``'s while it is ahead of her bow (``hx·rx + hy·ry > 0``)."""
    steps, n = x.shape
    out = np.zeros(n, np.bool_)
    side = np.sign(now)
    for t in range(steps):
        tx, ty = px + vx * times[t], py + vy * times[t]
        for s in range(n):
            rx, ry = x[t, s] - tx, y[t, s] - ty
            out[s] |= (np.sign(hx * ry - hy * rx) != side) & (hx * rx + hy * ry > 0)
    return out


@declared(_F[::1](_ROWS, _F[::1], _F[::1]), **_OPTIONS)
def weighted_shares(shares, sums, scales) -> np.ndarray:
    """The score of :meth:`usvtool.sim.controllers.base.DynamicWindow.score`: over the critics
    ``c`` in order, from zero, ``total += scales[c] * normalise(...)``, where ``shares[c]`` is
    the critic's reward already zero off the candidates and ``sums[c]`` its (NumPy's pairwise)
    sum: the share ``shares[c] / sums[c]``, zero when the sum is not positive
    (:func:`usvtool.sim.controllers.base.normalise`, UDWA eqs. 2-4)."""
    critics, n = shares.shape
    total = np.zeros(n)
    for c in range(critics):
        scale, whole = scales[c], sums[c]
        if whole > 0:
            for s in range(n):
                total[s] += scale * (shares[c, s] / whole)
        else:
            for s in range(n):
                total[s] += scale * 0.0
    return total


@declared(_F[::1](_F[::1], _B[::1]), **_OPTIONS)
def heading_reward(off, reached) -> np.ndarray:
    """A heading critic's reward from the unwrapped angle ``off`` between a heading and a
    bearing: ``np.where(reached, pi, pi - |wrap_pi(off)|)``, :func:`usvtool.angles.wrap_pi`'s
    ``(a + pi) % 2 pi - pi`` (the floor modulo in both).

    The modulo (``frem``, some 25 ns) is needed only outside ``(-2 pi, 2 pi)`` and at zero:
    inside, the floor modulo is ``a`` itself for a positive ``a`` (``fmod`` is exact) and ``a
    + 2 pi`` for a negative one (Python's and NumPy's adjustment of ``fmod``'s sign), which the
    first loop computes, vectorised; the others are found and redone with the modulo apart (in
    one loop with a branch LLVM would compute the modulo for every sample)."""
    n = off.size
    b = 2 * np.pi
    out = np.empty(n)
    rest = 0
    for s in range(n):
        a = off[s] + np.pi
        wrapped = (a if a > 0.0 else a + b) - np.pi  # a % b, for -b < a < b and a != 0
        out[s] = np.pi if reached[s] else np.pi - abs(wrapped)
        rest += not ((-b < a) & (a < b) & (a != 0.0))
    if rest:
        slow = np.empty(rest, np.int64)
        i = 0
        for s in range(n):
            a = off[s] + np.pi
            if not ((-b < a) & (a < b) & (a != 0.0)):
                slow[i] = s
                i += 1
        for s in slow:
            wrapped = (off[s] + np.pi) % b - np.pi
            out[s] = np.pi if reached[s] else np.pi - abs(wrapped)
    return out


@declared(_F[::1](_F[::1]), **_OPTIONS)
def wrap_angles(a) -> np.ndarray:
    """:func:`usvtool.angles.wrap_pi` of a vector, ``(a + pi) % 2 pi - pi``, with the floor
    modulo only where it is needed, as :func:`heading_reward` takes it."""
    n = a.size
    b = 2 * np.pi
    out = np.empty(n)
    rest = 0
    for s in range(n):
        x = a[s] + np.pi
        out[s] = (x if x > 0.0 else x + b) - np.pi  # x % b, for -b < x < b and x != 0
        rest += not ((-b < x) & (x < b) & (x != 0.0))
    if rest:
        slow = np.empty(rest, np.int64)
        i = 0
        for s in range(n):
            x = a[s] + np.pi
            if not ((-b < x) & (x < b) & (x != 0.0)):
                slow[i] = s
                i += 1
        for s in slow:
            out[s] = (a[s] + np.pi) % b - np.pi
    return out


@declared(nt.Tuple((_B[::1], _B[::1]))(_F[::1], _B[::1], _B[::1]), **_OPTIONS)
def candidates(contact, removed, intrudes) -> tuple[np.ndarray, np.ndarray]:
    """The first candidates of :meth:`usvtool.sim.controllers.base.DynamicWindow.decide`:
    ``(free, candidates)``, ``free`` the samples with no contact (``~np.isfinite(contact)``),
    the candidates those less the ``removed`` ones and, when some candidate stays out of the
    own ship's domain, less those that bring a target into it (``intrudes``)."""
    n = contact.size
    free, chosen = np.empty(n, np.bool_), np.empty(n, np.bool_)
    outside = False
    for s in range(n):
        free[s] = not np.isfinite(contact[s])
        chosen[s] = free[s] and not removed[s]
        outside |= chosen[s] and not intrudes[s]
    if outside:
        for s in range(n):
            chosen[s] = chosen[s] and not intrudes[s]
    return free, chosen


# -- vo (usvtool.sim.controllers.vo): its candidates and velocity obstacles -----------------


_VO_GRID = nt.Tuple((_F[::1], _F[::1], _I[::1], _F[::1]))


@declared(_VO_GRID(_F, _F, _F[::1], _F, _B, _F, _F, _I), **_OPTIONS)
def vo_candidates(psi, v, offsets, off, with_off, lo, hi, n):
    """:meth:`usvtool.sim.controllers.vo.VelocityObstacle.candidates`: ``(speed, heads, index,
    course)``, the ``n`` speeds of ``np.linspace(lo, hi, n)`` (:func:`axis`'s values, without
    extras) each with every course ``heads = psi + [offsets, 0, off]`` (``off`` only
    ``with_off``), the present velocity ``(v, psi)`` last, ``course = heads[index]``."""
    h = offsets.size + (2 if with_off else 1)
    heads = np.empty(h)
    for i in range(offsets.size):
        heads[i] = psi + offsets[i]
    heads[offsets.size] = psi + 0.0
    if with_off:
        heads[h - 1] = psi + off
    speeds = np.empty(n)  # np.linspace(lo, hi, n), n >= 2, as it computes it
    delta = hi - lo
    step = delta / (n - 1)
    for i in range(n):
        speeds[i] = (i * step if step != 0 else i / (n - 1) * delta) + lo
    speeds[n - 1] = hi
    count = n * h + 1
    speed, index, course = np.empty(count), np.empty(count, np.int64), np.empty(count)
    for i in range(n):
        for k in range(h):
            speed[i * h + k], index[i * h + k], course[i * h + k] = speeds[i], k, heads[k]
    speed[-1], index[-1], course[-1] = v, offsets.size, heads[offsets.size]
    return speed, heads, index, course


@declared(_F[::1](_F[::1], _F[::1], _F[::1], _F[::1], _ROWS, _F[::1], _F, _F), **_OPTIONS)
def vo_contacts(vx, vy, px, py, vel, radius, spread, horizon) -> np.ndarray:
    """The first contact of each candidate velocity ``(vx, vy)`` over the targets (at ``(px,
    py)`` from the own ship, moving at ``vel``): :func:`usvtool.sim.controllers.vo.
    _first_contact` of the relative velocities and its minimum over the targets (NaN
    propagating, as ``np.min``), the same operations in the same order (``np.sqrt`` is
    correctly rounded, as ``math.sqrt``)."""
    n, k = vx.size, px.size
    out = np.empty(n)
    for s in range(n):
        low = np.inf
        for j in range(k):
            wx, wy = vx[s] - vel[j, 0], vy[s] - vel[j, 1]
            a = wx * wx + wy * wy - spread * spread
            half_b = px[j] * wx + py[j] * wy + radius[j] * spread
            c = px[j] * px[j] + py[j] * py[j] - radius[j] * radius[j]
            disc = half_b * half_b - a * c
            ok = (disc >= 0.0) & ((half_b > 0.0) | (a < 0.0))
            t = c / ((half_b + math.sqrt(disc)) if ok else 1.0)
            t = t if ok & (t <= horizon) else np.inf
            t = 0.0 if c <= 0.0 else t
            if j == 0 or (not math.isnan(low) and (math.isnan(t) or t < low)):
                low = t
        out[s] = low
    return out


@declared(_B[::1](_ROWS, _ROWS, _F, _F, _F, _F, _F, _F), **_OPTIONS)
def vo_near(pos, vel, x, y, own_vx, own_vy, time, distance) -> np.ndarray:
    """The CPA entry test of :meth:`usvtool.sim.controllers.vo.VelocityObstacle.colregs` for
    each target at ``pos`` moving at ``vel`` (``(k, 2)``), the own ship at ``(x, y)`` moving at
    ``(own_vx, own_vy)``: ``0 < t_CPA <= time`` and ``d_CPA <= distance``, ``t_CPA`` zero for
    a relative speed below ``VEL_EPS`` (:func:`usvtool.encounter.cpa`'s), ``d_CPA`` by
    ``hypot`` (the C library's in both)."""
    k = pos.shape[0]
    near = np.empty(k, np.bool_)
    for j in range(k):
        rx, ry = pos[j, 0] - x, pos[j, 1] - y
        wx, wy = vel[j, 0] - own_vx, vel[j, 1] - own_vy
        ww = wx * wx + wy * wy
        tcpa = -(rx * wx + ry * wy) / ww if ww > VEL_EPS * VEL_EPS else 0.0
        dcpa = math.hypot(rx + tcpa * wx, ry + tcpa * wy)
        near[j] = (tcpa > 0) & (tcpa <= time) & (dcpa <= distance)
    return near


@declared(_F[::1](_F[::1], _F[::1], _I, _F, _F[::1], _F, _B), **_OPTIONS)
def favour(score, omega, side, factor, clearance, cap, safe) -> np.ndarray:
    """:meth:`usvtool.sim.controllers.side_rule.SideRule.favour` with a side: ``score`` times
    ``factor`` (``1 + priority``) where the yaw rate turns to ``side`` (``np.sign(omega) ==
    side``, the sign of a NaN matching no side) and, with ``safe``, the clearance reaches
    ``cap``; ``score`` elsewhere."""
    out = np.empty(score.size)
    for s in range(score.size):
        sign = (omega[s] > 0.0) - (omega[s] < 0.0)
        bonus = sign == side and (not safe or clearance[s] >= cap)
        out[s] = score[s] * factor if bonus else score[s]
    return out


@declared(nt.Tuple((_F[::1], _F[::1]))(_C[::1], _F, _F), **_OPTIONS)
def offsets(points, px, py) -> tuple[np.ndarray, np.ndarray]:
    """``(py - points.imag, px - points.real)``: the offsets from the points ``x + iy`` to
    ``(px, py)``, north and east (the arguments of ``np.arctan2``), in one pass."""
    north, east = np.empty(points.size), np.empty(points.size)
    for s in range(points.size):
        north[s], east[s] = py - points[s].imag, px - points[s].real
    return north, east
