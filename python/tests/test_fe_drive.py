"""fe_run_up on a drive (the non-ideal drive: the speed a state, driven by a motor through the
polar inertia): against an independent solve written here from Lagrange's equations (fixed-step
RK4 in numpy, the shaft's acceleration and the rotor's solved together at every stage, the
ring's contacts located by the secant method); the revolutions at the shaft's turns; the
motor's table against numpy's interpolation; bad input."""

import math

import numpy as np
import pytest

import jeffcott
from test_fe_run_up import GAP, KS, ME, PHASE, matrices

# A DC motor T = T0 (1 - w / W0) through J from 6 rad/s towards 20 rad/s, the
# out-of-balance's reaction torque at the critical (near 10 rad/s) of the motor's order.
T0, W0, J, W_START, T_END = 0.6, 20.0, 0.1, 6.0, 6.0


def motor_torque(w):
    return T0 * (1.0 - w / W0)


def field(z, contact, mats):
    """z = [q (4), q' (4), w, phi]. Lagrange's equations with the out-of-balance's kinetic
    energy w q'.b(phi), b = ME (-sin, cos) at x, y: M q'' - w' u = F and J w' - u.q'' = T,
    u = ME (sin phi, -cos phi, 0, 0), F = ME w^2 (cos, sin) - (C + w G) q' - K q + the ring's
    force; the two solved as one linear system."""
    M, K, C, G = mats
    q, v, w, phi = z[:4], z[4:8], z[8], z[9]
    u = ME * np.array([math.sin(PHASE + phi), -math.cos(PHASE + phi), 0.0, 0.0])
    f = np.zeros(4)
    f[0] = ME * w * w * math.cos(PHASE + phi)
    f[1] = ME * w * w * math.sin(PHASE + phi)
    if contact:
        r = math.hypot(q[0], q[1])
        f[:2] -= KS * (r - GAP) * q[:2] / r
    f -= (C + w * G) @ v + K @ q
    A = np.zeros((5, 5))
    A[:4, :4], A[:4, 4], A[4, :4], A[4, 4] = M, -u, -u, J
    sol = np.linalg.solve(A, np.concatenate([f, [motor_torque(w)]]))
    return np.concatenate([v, sol[:4], [sol[4], w]])


def rk4(z, h, contact, mats):
    k1 = field(z, contact, mats)
    k2 = field(z + h / 2 * k1, contact, mats)
    k3 = field(z + h / 2 * k2, contact, mats)
    k4 = field(z + h * k3, contact, mats)
    return z + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


def independent_drive(t_end, h, ring, every):
    """Samples [x, y, w, phi] every ``every`` steps of h and the times the rotor crosses the gap
    (each crossing step cut there by the secant method on the step length)."""
    mats = matrices()
    z, t, contact = np.zeros(10), 0.0, False
    z[8] = W_START
    depth = lambda z: math.hypot(z[0], z[1]) - GAP
    samples, crossings = [z[[0, 1, 8, 9]].copy()], []
    for i in range(round(t_end / h)):
        t_next = (i + 1) * h
        while True:
            nxt = rk4(z, t_next - t, contact, mats)
            if not ring or (depth(nxt) > 0) == contact:
                break
            a, b, da, db = 0.0, t_next - t, depth(z), depth(nxt)
            for _ in range(60):
                s = b - db * (b - a) / (db - da)
                ds = depth(rk4(z, s, contact, mats))
                a, da, b, db = b, db, s, ds
                if abs(b - a) < 1e-14:
                    break
            z, t, contact = rk4(z, b, contact, mats), t + b, not contact
            crossings.append(t)
        z, t = nxt, t_next
        if (i + 1) % every == 0:
            samples.append(z[[0, 1, 8, 9]].copy())
    return np.array(samples), np.array(crossings)


def crate_drive(ring, **kw):
    M, K, C, G = matrices()
    args = dict(ring_node=0, gap=GAP, ring_stiffness=KS, ring_damping=0.0,
                unbalance=[(0, ME, PHASE)], layout="lateral4", ring=ring, rtol=1e-11,
                motor=jeffcott.Motor.linear(T0, W0), inertia=J, speed0=W_START, t_end=T_END)
    args.update(kw)
    return jeffcott.fe_run_up(M, K, C, G, **args)


@pytest.mark.parametrize("ring", [False, True])
def test_fe_drive_follows_an_independent_solve(ring):
    dt = 2e-3
    truth, crossings = independent_drive(T_END, dt / 4, ring, every=4)
    run = crate_drive(ring, dt=dt)
    assert run.t.shape == (len(truth),)
    scale = np.max(np.hypot(truth[:, 0], truth[:, 1]))
    err = np.max(np.hypot(run.x - truth[:, 0], run.y - truth[:, 1])) / scale
    assert err <= 5e-8, f"{err:e} of the largest radius"
    assert np.max(np.abs(run.speed - truth[:, 2])) <= 1e-8 * W0
    assert np.max(np.abs(run.phase - truth[:, 3])) <= 1e-8 * truth[-1, 3]
    # The Sommerfeld effect: without the ring the motor cannot pass the critical (the
    # out-of-balance's reaction torque at resonance takes its torque: the speed hangs near 10
    # rad/s); the ring holds the whirl down and the rotor passes (16 rad/s at the end).
    if ring:
        assert run.speed[-1] > 12.0
    else:
        assert np.max(run.speed) < 11.0
    if ring:
        assert scale > GAP and len(run.onsets) >= 2
        times = np.sort(np.concatenate([run.onsets, run.losses]))
        assert times.shape == crossings.shape
        assert np.max(np.abs(times - crossings)) <= 1e-7
    else:
        assert len(run.onsets) == 0


def test_fe_drive_revolutions_are_the_shafts_turns():
    # Each revolution from one turn of the shaft's angle (the state's) to the next: its ends
    # between the samples whose angles bracket 2 pi k, one a turn the samples pass.
    run = crate_drive(True, dt=1e-3)
    rev = run.revolutions
    turns = int(run.phase[-1] // (2 * math.pi))
    assert len(rev.start) == turns and rev.start[0] == 0.0
    ends = np.concatenate([rev.start, rev.end[-1:]])
    for k, t in enumerate(ends):
        after = np.searchsorted(run.phase, 2 * math.pi * k)
        assert run.t[after - 1] <= t <= run.t[after] if k > 0 else t == 0.0
        # The angle there, interpolated linearly between those samples, within the chord's
        # error (the speed changes by at most 1e-3 * max |w'| across a sample interval).
        if k > 0:
            s = (t - run.t[after - 1]) / (run.t[after] - run.t[after - 1])
            chord = run.phase[after - 1] + s * (run.phase[after] - run.phase[after - 1])
            assert abs(chord - 2 * math.pi * k) <= 1e-5
    assert np.allclose(rev.speed, 2 * math.pi / (rev.end - rev.start), rtol=1e-15)


def test_fe_drive_with_friction_is_braked_by_the_rub_torque():
    # The shaft's equation read off the samples (central differences of the speed and the
    # ring node's velocity, away from the events): J w' - T(w) - u.q'' is ``rub_torque``,
    # a f_t (f_t the ring's force on the rotor along the tangent, ``friction_force``; the
    # contact point at a n from the shaft's centre), which brakes the shaft.
    a, h = 0.05, 1e-4
    run = crate_drive(True, rtol=1e-10, dt=h, t_end=3.0, friction=0.3, shaft_radius=a)
    assert len(run.onsets) >= 1
    d = lambda v: (v[2:] - v[:-2]) / (2 * h)
    phi = PHASE + run.phase[1:-1]
    u_dot_acc = ME * (np.sin(phi) * d(run.vx) - np.cos(phi) * d(run.vy))
    residual = J * d(run.speed) - motor_torque(run.speed[1:-1]) - u_dot_acc
    rub = run.rub_torque[1:-1]
    labels = run.regimes
    steady = (labels[:-2] == labels[1:-1]) & (labels[2:] == labels[1:-1])
    events = np.concatenate([run.onsets, run.losses])
    far = np.min(np.abs(run.t[1:-1, None] - events[None, :]), axis=1) > 3 * h
    keep = steady & far
    in_contact = keep & (labels[1:-1] != 1)
    assert in_contact.sum() > 1000
    size = np.max(np.abs(rub[in_contact]))
    assert size > 0.05 * T0  # the rub torque is of the motor's order: it shows
    assert np.max(np.abs(residual[keep] - rub[keep])) <= 1e-3 * size
    assert np.mean(rub[in_contact]) < 0  # it brakes


def test_motor_table_is_linear_between_its_points_and_held_beyond():
    w = np.array([0.0, 5.0, 12.0, 20.0])
    t = np.array([1.0, 0.8, 0.2, -0.4])
    motor = jeffcott.Motor.table(list(w), t.astype(np.float32))
    probe = np.linspace(-3.0, 25.0, 113)
    got = np.array([motor.torque(x) for x in probe])
    want = np.interp(probe, w, t.astype(np.float32).astype(np.float64))
    assert np.max(np.abs(got - want)) <= 1e-15
    # Its no-load speed: where the torque crosses zero (between 12 and 20 rad/s).
    assert motor.no_load_speed == pytest.approx(12.0 + 8.0 * 0.2 / 0.6, rel=1e-6)
    assert jeffcott.Motor.linear(2.0, 30.0).no_load_speed == 30.0
    assert jeffcott.Motor.linear(2.0, 30.0).torque(15.0) == 1.0
    assert "Motor.linear" in repr(jeffcott.Motor.linear(2.0, 30.0))


@pytest.mark.parametrize("speeds, torques, message", [
    ([0.0], [1.0], "at least 2"),
    ([0.0, 1.0], [1.0], "as long"),
    ([0.0, 0.0], [1.0, 0.5], "increase"),
    ([0.0, np.nan], [1.0, 0.5], "finite"),
])
def test_motor_table_bad_input(speeds, torques, message):
    with pytest.raises(ValueError, match=message):
        jeffcott.Motor.table(speeds, torques)


@pytest.mark.parametrize("kw, message", [
    (dict(inertia=None), "motor, inertia and speed0"),
    (dict(speed0=None), "motor, inertia and speed0"),
    (dict(speed0=-1.0), "speed0"),
    (dict(t_end=None), "t_end"),
    (dict(inertia=1e-9), "nertia"),
])
def test_fe_drive_bad_input(kw, message):
    with pytest.raises(ValueError, match=message):
        crate_drive(True, **kw)


def test_fe_run_up_takes_a_table_or_a_drive_not_both():
    M, K, C, G = matrices()
    with pytest.raises(ValueError, match="not both"):
        jeffcott.fe_run_up(M, K, C, G, [0.0, 1.0], [6.0, 8.0], ring_node=0, gap=GAP,
                           ring_stiffness=KS, ring_damping=0.0, unbalance=[(0, ME, PHASE)],
                           layout="lateral4", motor=jeffcott.Motor.linear(T0, W0),
                           inertia=J, speed0=W_START)
    with pytest.raises(ValueError, match="times and speeds"):
        jeffcott.fe_run_up(M, K, C, G, ring_node=0, gap=GAP, ring_stiffness=KS,
                           ring_damping=0.0, unbalance=[(0, ME, PHASE)], layout="lateral4")


def test_ross_rotor_drive_reads_its_bearings_from_the_start_to_no_load():
    # FeRotor.run_up on a drive reads rotor.K(w, w), rotor.C(w, w) on 33 speeds from speed0
    # to the motor's no-load speed: the same run as fe_run_up given that grid.
    from jeffcott.ross import FeRotor
    from test_fe_run_up import BearingRotor, bearing_at

    M, _, _, G = matrices()
    K, C = bearing_at(W0)
    fe = FeRotor(M, K, C, G, W0, np.array([0.01]), BearingRotor())
    motor = jeffcott.Motor.linear(T0, W0)
    args = dict(ring_node=0, gap=GAP, ring_stiffness=KS, ring_damping=0.0,
                unbalance=[(0, ME, PHASE)], layout="lateral4", rtol=1e-9, dt=2e-2,
                motor=motor, inertia=J, speed0=W_START, t_end=2.0)
    grid = np.linspace(W_START, W0, 33)
    Ks, Cs = (np.array(a) for a in zip(*(bearing_at(w) for w in grid)))
    direct = jeffcott.fe_run_up(M, K, C, G, bearing_speeds=grid, bearing_K=Ks, bearing_C=Cs,
                                **args)
    assert np.array_equal(fe.run_up(**args).x, direct.x)
    fixed = jeffcott.fe_run_up(M, K, C, G, **args)
    assert not np.array_equal(fixed.x, direct.x)


def test_fe_rub_outputs_against_the_samples():
    # The slip velocity against the contact direction's turning read off the samples: n the
    # direction of (x, y) - (ring_x, ring_y), v = gap theta' + speed a (theta' by central
    # differences); the whirl rate against the turning of (x, y); the friction's power is
    # -f_t v (>= 0 while slipping, 0 rolling or free), its energy the trapezoid of the power.
    a, h = 0.05, 1e-4
    run = crate_drive(True, rtol=1e-10, dt=h, t_end=3.0, friction=0.3, shaft_radius=a)
    labels = run.regimes
    inner = slice(1, -1)
    steady = (labels[:-2] == labels[1:-1]) & (labels[2:] == labels[1:-1])
    events = np.concatenate([run.onsets, run.losses])
    far = np.min(np.abs(run.t[inner, None] - events[None, :]), axis=1) > 3 * h
    slipping = steady & far & ((labels[inner] == 6) | (labels[inner] == 7))
    assert slipping.sum() > 1000
    theta = np.unwrap(np.arctan2(run.y - run.ring_y, run.x - run.ring_x))
    v_fd = GAP * (theta[2:] - theta[:-2]) / (2 * h) + run.speed[inner] * a
    v = run.slip_velocity[inner]
    size = np.max(np.abs(v[slipping]))
    assert np.max(np.abs(v[slipping] - v_fd[slipping])) <= 1e-5 * size
    assert np.all(np.isnan(run.slip_velocity[labels == 1]))
    assert np.all(run.slip_velocity[labels == 8] == 0.0)
    psi = np.unwrap(np.arctan2(run.y, run.x))
    w_fd = (psi[2:] - psi[:-2]) / (2 * h)
    # (Away from the start at rest, where the angle of (x, y) is not defined.)
    free_or_steady = steady & far & (np.hypot(run.x, run.y)[inner] > 0.1 * GAP)
    rate = run.whirl_rate[inner]
    assert np.max(np.abs(rate[free_or_steady] - w_fd[free_or_steady])) <= 1e-4 * np.max(
        np.abs(rate[free_or_steady]))
    power = run.friction_power
    assert np.all(power >= -1e-12 * np.max(power)) and np.max(power) > 0
    assert np.array_equal(power[labels != 6][labels[labels != 6] != 7], np.zeros(np.sum((labels != 6) & (labels != 7))))
    slip = (labels == 6) | (labels == 7)
    assert np.allclose(power[slip], -run.friction_force[slip] * run.slip_velocity[slip], rtol=1e-15)
    assert run.friction_energy == pytest.approx(np.trapezoid(power, run.t), rel=1e-12)
    # Without friction: no slip velocity, torque, power or energy.
    free = crate_drive(True, rtol=1e-9, dt=1e-3, t_end=1.0)
    assert np.all(np.isnan(free.slip_velocity)) and np.all(free.rub_torque == 0)
    assert np.all(free.friction_power == 0) and free.friction_energy == 0


def test_fe_runs_say_which_method_ran():
    # The default picked (fe_run_up: radau5 for the full model, dop853 reduced, etd4 in modal
    # form) or the one asked for, lower case.
    M, K, C, G = matrices()
    ring = dict(ring_node=0, gap=GAP, ring_stiffness=KS, ring_damping=0.0,
                unbalance=[(0, ME, PHASE)], layout="lateral4")
    up = lambda **kw: jeffcott.fe_run_up(M, K, C, G, [0.0, 0.5], [6.0, 7.0], dt=0.05, **ring,
                                         **kw).method
    assert up() == "radau5"
    assert up(modes=1) == "dop853"
    assert up(method="DOPRI5") == "dopri5"
    assert crate_drive(True, t_end=0.5, dt=0.05).method == "radau5"
    run = lambda **kw: jeffcott.fe_transient(M, K, C, G, 8.0, t_end=0.5, samples=10, **ring,
                                             **kw).method
    # fe_transient's default for the full model: the modal form with etd4; the physical
    # form's radau5, a reduced rotor's dop853, or a probe's physical form on request.
    assert run() == "etd4" and run(form="modal") == "etd4"
    assert run(form="physical") == "radau5" and run(modes=1) == "dop853"
    assert run(probe_nodes=[0]) == "radau5" and run(method="etd4") == "etd4"
    assert run(form="modal", method="dop853") == "dop853"
