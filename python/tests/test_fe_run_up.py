"""fe_run_up: a finite-element rotor through its critical speed, against an independent
solve written here (fixed-step RK4 in numpy, the ring's contacts located by the secant
method); the contact force against the ring element's force law; the per-revolution peak
against a fine sampling."""

import math

import numpy as np
import pytest

import jeffcott
from conftest import interrupted_after

# One node (layout lateral4: x, y, alpha, beta): mass 1, tilt inertia 0.02, polar 0.04; the
# tilts coupled to x, y by kc; the critical near 10 rad/s.
K_LAT, KC, K_TILT, C_LAT = 100.0, 5.0, 60.0, 0.2
ME, PHASE = 0.02, 0.3
GAP, KS = 0.1, 2000.0
TIMES, SPEEDS = [0.0, 6.0, 8.0], [6.0, 14.0, 14.0]


def matrices():
    M = np.diag([1.0, 1.0, 0.02, 0.02])
    K = np.array([[K_LAT, 0, 0, KC], [0, K_LAT, -KC, 0], [0, -KC, K_TILT, 0], [KC, 0, 0, K_TILT]])
    C = np.diag([C_LAT, C_LAT, 0.01, 0.01])
    G = np.zeros((4, 4))
    G[2, 3], G[3, 2] = 0.04, -0.04
    return M, K, C, G


def speed_at(t, piece_of=None):
    """The table's speed, its rate and its phase (the integral of the speed) at t, on the
    piece that holds ``piece_of`` (default t) continued: a step that ends on a break keeps
    its piece's rate (the rate jumps there)."""
    piece_of = t if piece_of is None else piece_of
    for (t0, t1), (w0, w1) in zip(zip(TIMES, TIMES[1:]), zip(SPEEDS, SPEEDS[1:])):
        if piece_of < t1:
            rate = (w1 - w0) / (t1 - t0)
            s = t - t0
            return w0 + rate * s, rate, phase_to(t0) + s * (w0 + 0.5 * rate * s)
    return SPEEDS[-1], 0.0, phase_to(TIMES[-1]) + SPEEDS[-1] * (t - TIMES[-1])


def phase_to(t_break):
    pairs = zip(zip(TIMES, TIMES[1:]), zip(SPEEDS, SPEEDS[1:]))
    return sum((t1 - t0) * (w0 + w1) / 2 for (t0, t1), (w0, w1) in pairs if t1 <= t_break)


def field(t, z, contact, t_step, M, K, C, G):
    """z = [q, q']; the ring force -KS (|r| - GAP) r/|r| on the contact side (its smooth
    extension inside the gap), none on the free side. K and C: matrices, or functions of the
    speed."""
    n = 4
    q, v = z[:n], z[n:]
    w, rate, phi = speed_at(t, t_step)
    K, C = (K(w), C(w)) if callable(K) else (K, C)
    f = np.zeros(n)
    f[0] = ME * (w * w * math.cos(PHASE + phi) + rate * math.sin(PHASE + phi))
    f[1] = ME * (w * w * math.sin(PHASE + phi) - rate * math.cos(PHASE + phi))
    if contact:
        r = math.hypot(q[0], q[1])
        f[:2] -= KS * (r - GAP) * q[:2] / r
    a = np.linalg.solve(M, f - (C + w * G) @ v - K @ q)
    return np.concatenate([v, a])


def rk4(t, z, h, contact, mats):
    k1 = field(t, z, contact, t, *mats)
    k2 = field(t + h / 2, z + h / 2 * k1, contact, t, *mats)
    k3 = field(t + h / 2, z + h / 2 * k2, contact, t, *mats)
    k4 = field(t + h, z + h * k3, contact, t, *mats)
    return z + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


def independent_run_up(t_end, h, ring, every, mats=None):
    """Samples every h and the times the rotor crosses the gap: each step that crosses is
    cut at the crossing (secant on the step length), so that no step straddles the kink (the
    table's breaks are multiples of h: none straddles a jump of the rate either). A sample
    every ``every`` steps. ``mats``: (M, K, C, G), default ``matrices()``."""
    mats = matrices() if mats is None else mats
    z, t, contact = np.zeros(8), 0.0, False
    samples, crossings = [z[:4].copy()], []
    depth = lambda z: math.hypot(z[0], z[1]) - GAP
    for i in range(round(t_end / h)):
        t_next = (i + 1) * h
        while True:
            nxt = rk4(t, z, t_next - t, contact, mats)
            if not ring or (depth(nxt) > 0) == contact:
                break
            a, b = 0.0, t_next - t  # the crossing's step length, bracketed
            da, db = depth(z), depth(nxt)
            for _ in range(60):
                s = b - db * (b - a) / (db - da)
                ds = depth(rk4(t, z, s, contact, mats))
                a, da, b, db = b, db, s, ds
                if abs(b - a) < 1e-14:
                    break
            z, t, contact = rk4(t, z, b, contact, mats), t + b, not contact
            crossings.append(t)
        z, t = nxt, t_next
        if (i + 1) % every == 0:
            samples.append(z[:4].copy())
    return np.array(samples), np.array(crossings)


def crate_run_up(ring, **kw):
    M, K, C, G = matrices()
    args = dict(ring_node=0, gap=GAP, ring_stiffness=KS, ring_damping=0.0,
                unbalance=[(0, ME, PHASE)], layout="lateral4", ring=ring, rtol=1e-11)
    args.update(kw)
    return jeffcott.fe_run_up(M, K, C, G, TIMES, SPEEDS, **args)


@pytest.mark.parametrize("ring", [False, True])
def test_fe_run_up_follows_an_independent_solve(ring):
    # RK4 at h = 5e-4 is within 2e-9 (free) and 7e-9 (on the ring) of its limit (measured by
    # halving h), the crate at rtol 1e-11 within 2e-9 and 1.2e-8 of it.
    dt = 2e-3
    truth, crossings = independent_run_up(TIMES[-1], dt / 4, ring, every=4)
    run = crate_run_up(ring, dt=dt)
    assert run.t.shape == (len(truth),)
    assert np.max(np.abs(run.speed - [speed_at(t)[0] for t in run.t])) <= 1e-12
    scale = np.max(np.hypot(truth[:, 0], truth[:, 1]))
    err = np.max(np.hypot(run.x - truth[:, 0], run.y - truth[:, 1])) / scale
    assert err <= 5e-8, f"{err:e} of the largest radius"
    if ring:
        # The rotor rides through the critical on the ring, and every contact matches.
        assert scale > GAP and len(run.onsets) >= 2
        times = np.sort(np.concatenate([run.onsets, run.losses]))
        assert times.shape == crossings.shape
        assert np.max(np.abs(times - crossings)) <= 1e-7
    else:
        assert len(run.onsets) == 0 and np.all(run.normal_force == 0)


# Bearings whose stiffness and damping follow the speed: a law sampled on five speeds.
BEARING_SPEEDS = np.array([5.0, 8.0, 10.0, 12.0, 15.0])


def bearing_at(w):
    """The bearing's K and C at the speed w (rad/s): stiffer and cross-coupled as it spins."""
    M, K, C, G = matrices()
    s = (w / 10.0) ** 2
    K = K.copy()
    K[0, 0] += 30.0 * s
    K[1, 1] += 20.0 * s
    K[0, 1] += 4.0 * s
    K[1, 0] -= 4.0 * s
    C = C.copy()
    C[0, 0] += 0.1 * s
    return K, C


class BearingRotor:
    """What FeRotor.run_up reads of a ross.Rotor: its bearings' K and C at a speed."""

    def K(self, frequency, speed):
        return bearing_at(speed)[0]

    def C(self, frequency, speed):
        return bearing_at(speed)[1]


def bearing_table():
    Ks, Cs = zip(*(bearing_at(w) for w in BEARING_SPEEDS))
    return np.array(Ks), np.array(Cs)


def interpolated(table):
    """The table's rule written out: each entry linear in the speed between the grid's
    speeds, held beyond them (numpy's interp)."""
    flat = table.reshape(len(BEARING_SPEEDS), -1)
    return lambda w: np.array([np.interp(w, BEARING_SPEEDS, col) for col in flat.T]).reshape(4, 4)


@pytest.mark.parametrize("ring", [False, True])
def test_fe_run_up_with_bearings_that_follow_the_speed(ring):
    # The independent solve above with K(w), C(w) by the table's rule; as tight as without.
    dt = 2e-3
    Ks, Cs = bearing_table()
    M, _, _, G = matrices()
    mats = (M, interpolated(Ks), interpolated(Cs), G)
    truth, crossings = independent_run_up(TIMES[-1], dt / 4, ring, every=4, mats=mats)
    run = crate_run_up(ring, dt=dt, bearing_speeds=BEARING_SPEEDS, bearing_K=Ks, bearing_C=Cs)
    scale = np.max(np.hypot(truth[:, 0], truth[:, 1]))
    err = np.max(np.hypot(run.x - truth[:, 0], run.y - truth[:, 1])) / scale
    assert err <= 5e-8, f"{err:e} of the largest radius"
    # The bearings matter: the run with K and C fixed is elsewhere.
    fixed = crate_run_up(ring, dt=dt)
    apart = np.max(np.hypot(fixed.x - run.x, fixed.y - run.y)) / scale
    assert apart > 1e-2, f"{apart:e}"
    if ring:
        times = np.sort(np.concatenate([run.onsets, run.losses]))
        assert times.shape == crossings.shape and len(run.onsets) >= 1
        assert np.max(np.abs(times - crossings)) <= 1e-7


@pytest.mark.parametrize(
    "kw, message",
    [
        (dict(bearing_speeds=BEARING_SPEEDS), "go together"),
        (dict(bearing_speeds=BEARING_SPEEDS[:3], bearing_K=np.zeros((5, 4, 4)),
              bearing_C=np.zeros((5, 4, 4))), "shape"),
        (dict(bearing_speeds=BEARING_SPEEDS[::-1], bearing_K=bearing_table()[0],
              bearing_C=bearing_table()[1]), "speeds"),
    ],
)
def test_fe_run_up_bad_bearings(kw, message):
    with pytest.raises(ValueError, match=message):
        crate_run_up(True, **kw)


def test_ross_rotor_run_up_reads_its_bearings_on_a_grid():
    # FeRotor.run_up reads rotor.K(w, w), rotor.C(w, w) on 33 speeds over the table's range:
    # the same run as fe_run_up given that grid; bearing_points=0 keeps K and C at `speed`.
    from jeffcott.ross import FeRotor

    M, _, _, G = matrices()
    K, C = bearing_at(14.0)
    fe = FeRotor(M, K, C, G, 14.0, np.array([0.01]), BearingRotor())
    args = dict(ring_node=0, gap=GAP, ring_stiffness=KS, ring_damping=0.0,
                unbalance=[(0, ME, PHASE)], layout="lateral4", rtol=1e-9, dt=2e-2)
    grid = np.linspace(6.0, 14.0, 33)
    Ks, Cs = (np.array(a) for a in zip(*(bearing_at(w) for w in grid)))
    direct = jeffcott.fe_run_up(M, K, C, G, TIMES, SPEEDS, bearing_speeds=grid, bearing_K=Ks,
                                bearing_C=Cs, **args)
    assert np.array_equal(fe.run_up(TIMES, SPEEDS, **args).x, direct.x)
    fixed = jeffcott.fe_run_up(M, K, C, G, TIMES, SPEEDS, **args)
    assert np.array_equal(fe.run_up(TIMES, SPEEDS, bearing_points=0, **args).x, fixed.x)


def test_fe_run_up_contact_force_is_the_ring_elements():
    # The element's law with no preload: the ring's unit springs and dampers push with
    # k_s s + c_s s' (s the ring's displacement, s' by central differences here), back on the
    # rotor.
    cs, h = 2.0, 1e-4
    run = crate_run_up(True, ring_damping=cs, dt=h, t_end=7.0)
    s = np.stack([run.ring_x, run.ring_y], axis=1)
    inside = np.flatnonzero((run.regimes[1:-1] != 1) & (run.regimes[:-2] != 1)
                            & (run.regimes[2:] != 1)) + 1
    assert len(inside) > 100
    s_dot = (s[inside + 1] - s[inside - 1]) / (2 * h)
    law = -(KS * s[inside] + cs * s_dot)
    force = np.stack([run.force_x, run.force_y], axis=1)[inside]
    size = np.max(np.linalg.norm(law, axis=1))
    damping = np.max(np.linalg.norm(cs * s_dot, axis=1))
    assert damping > 0.01 * size  # the damping part matters in this check
    assert np.max(np.linalg.norm(force - law, axis=1)) <= 1e-4 * size
    # The normal force: the push along the normal n = (r - s)/|r - s| (the damping's part
    # across it is not normal: s' has a tangential part).
    n = np.stack([run.x, run.y], axis=1)[inside] - s[inside]
    n /= np.linalg.norm(n, axis=1)[:, None]
    assert np.allclose(run.normal_force[inside], -np.sum(n * force, axis=1), rtol=1e-9)
    assert np.all(run.normal_force >= 0) and np.all(run.normal_force[run.regimes == 1] == 0)
    # Each episode: start and end among the events, the peak at least the samples', the
    # impulse the integral of the normal force (numpy's trapezoid on these samples).
    c = run.contacts
    assert np.array_equal(c.start, run.onsets[: len(c.start)])
    done = ~np.isnan(c.end)
    assert np.array_equal(c.end[done], run.losses[: done.sum()])
    for a, b, peak, impulse in zip(c.start[done], c.end[done], c.peak_force, c.impulse):
        inner = (run.t > a) & (run.t < b)
        assert peak >= np.max(run.normal_force[inner], initial=0.0)
        trapz = np.trapezoid(run.normal_force[inner], run.t[inner])
        assert abs(impulse - trapz) <= 1e-3 * impulse + 2 * h * peak


def test_fe_run_up_peak_per_revolution_is_located():
    # The default sampling (128 a revolution at the top speed) against a sampling 16 times
    # finer (2048): each revolution's located peak at least the fine samples' largest radius
    # and, where that largest is inside the revolution (not at its ends), within 2e-6 above it
    # (the fine samples' own error: (2 pi / 2048)^2 / 8 = 1.2e-6); the fine run's located
    # peak within 1e-7 (measured: 3.4e-8, the coarse knots' interpolation error in contact).
    # The coarse samples' own largest is up to 1.7e-3 low.
    coarse = crate_run_up(True)
    fine = crate_run_up(True, dt=2 * math.pi / SPEEDS[-1] / 128 / 16)
    rev = coarse.revolutions
    assert np.allclose(fine.revolutions.start, rev.start, rtol=0, atol=1e-12)
    radius = lambda r: np.hypot(r.x, r.y)
    worst_sampled, interior = 0.0, 0
    for a, b, peak, fine_peak in zip(rev.start, rev.end, rev.peak_radius,
                                     fine.revolutions.peak_radius):
        inner = radius(fine)[(fine.t >= a) & (fine.t <= b)]
        j = np.argmax(inner)
        assert peak >= inner[j] - 1e-7 * peak
        if 2 <= j < len(inner) - 2:
            interior += 1
            assert peak - inner[j] <= 2e-6 * peak, (a, peak, inner[j])
        assert abs(peak - fine_peak) <= 1e-7 * peak
        coarse_peak = np.max(radius(coarse)[(coarse.t >= a) & (coarse.t <= b)])
        worst_sampled = max(worst_sampled, (peak - coarse_peak) / peak)
    assert interior >= 5
    assert worst_sampled > 1e-4, worst_sampled
    # A revolution is a turn of the forcing phase (the table's phase, written out here).
    turns = [(speed_at(b)[2] - speed_at(a)[2]) / (2 * math.pi) for a, b in zip(rev.start, rev.end)]
    assert np.allclose(turns, 1.0, rtol=0, atol=1e-12) and rev.start[0] == 0.0
    assert np.allclose(rev.speed, 2 * math.pi / (rev.end - rev.start), rtol=1e-15)
    assert np.array_equal(rev.contact_time > 0, rev.peak_radius > GAP)


@pytest.mark.parametrize("times, speeds, kw", [
    ([0.0, 1.0], [5.0], {}),
    ([1.0, 2.0], [5.0, 6.0], {}),
    ([0.0, 1.0, 1.0], [5.0, 6.0, 7.0], {}),
    ([0.0, 1.0], [5.0, -6.0], {}),
    ([0.0], [5.0], {}),
    ([0.0, 1.0], [5.0, 6.0], {"dt": 0.0}),
])
def test_fe_run_up_bad_profile(times, speeds, kw):
    M, K, C, G = matrices()
    with pytest.raises(ValueError):
        jeffcott.fe_run_up(M, K, C, G, times, speeds, ring_node=0, gap=GAP, ring_stiffness=KS,
                           ring_damping=0.0, unbalance=[(0, ME, 0.0)], layout="lateral4", **kw)


def test_ctrl_c_stops_a_long_fe_run_up():
    # One run of the crate's driver, stopped by its observer on Ctrl-C (no chunks).
    M, K, C, G = matrices()
    long_run = lambda: jeffcott.fe_run_up(
        M, K, C, G, [0.0, 1e6], [6.0, 14.0], ring_node=0, gap=GAP, ring_stiffness=KS,
        ring_damping=0.0, unbalance=[(0, ME, PHASE)], layout="lateral4", rtol=1e-11)
    elapsed = interrupted_after(0.5, long_run)
    assert elapsed < 5.0, elapsed
