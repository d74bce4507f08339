"""Spectra and order tracking from Python, against signals whose whirls are known in closed
form, and on a finite-element run-up (its 1x whirl against its per-revolution peak)."""

import math

import numpy as np
import pytest

import jeffcott


def test_full_spectrum_separates_forward_and_backward_whirl():
    # x + i y = 0.3 e^{i 2 pi 5 t} + 0.1 e^{-i 2 pi 12 t}, both on bins (1 s, 256 samples):
    # the forward radius 0.3 at 5 Hz, the backward 0.1 at 12 Hz, nothing else above rounding
    # beyond the Hann window's two neighbours.
    t = np.arange(256) / 256.0
    z = 0.3 * np.exp(2j * np.pi * 5 * t) + 0.1 * np.exp(-2j * np.pi * 12 * t)
    s = jeffcott.full_spectrum(t, z.real, z.imag)
    assert s.frequency.shape == s.forward.shape == s.backward.shape == (128,)
    assert s.frequency[5] == 5.0 and s.frequency[12] == 12.0
    assert abs(s.forward[5] - 0.3) <= 1e-12 and abs(s.backward[12] - 0.1) <= 1e-12
    far = np.ones(128, bool)
    far[4:7] = False
    assert np.max(s.forward[far]) <= 1e-12
    far[:] = True
    far[11:14] = False
    assert np.max(s.backward[far]) <= 1e-12
    rect = jeffcott.full_spectrum(t, z.real, z.imag, window="rectangular")
    assert abs(rect.forward[5] - 0.3) <= 1e-12 and np.max(rect.forward[6:]) <= 1e-12


def test_amplitude_spectrum_of_a_cosine():
    t = np.arange(200) * 0.01
    f, a = jeffcott.amplitude_spectrum(t, 2.0 * np.cos(2 * np.pi * 7 * t + 0.4) + 0.5)
    assert f[14] == pytest.approx(7.0) and a[14] == pytest.approx(2.0, abs=1e-12)


def test_order_track_through_a_ramp():
    # A run-up Phi(t) = 20 t + 3 t^2 (speed 20 -> 80 rad/s over 10 s) whose orbit is a 1x
    # forward whirl of radius A(t) = 1 + 0.05 t and a 2x backward whirl of 0.2, recorded 64
    # times a revolution of the top speed: order 1 forward reads A at each window's centre
    # (to the window's averaging of the linear growth), order 2 backward 0.2.
    t = np.arange(0.0, 10.0, 2 * np.pi / 80 / 64)
    phase = 20 * t + 3 * t * t
    z = (1 + 0.05 * t) * np.exp(1j * phase) + 0.2 * np.exp(-2j * phase)
    track = jeffcott.order_track(t, phase, z.real, z.imag, orders=[1.0, 2.0])
    assert track.forward.shape == track.backward.shape == (len(track.time), 2)
    assert len(track.time) > 20
    assert np.allclose(track.speed, 20 + 6 * track.time, rtol=1e-6)
    assert np.max(np.abs(track.forward[:, 0] - (1 + 0.05 * track.time))) <= 2e-3
    assert np.max(np.abs(track.backward[:, 1] - 0.2)) <= 1e-4
    assert np.max(track.backward[:, 0]) <= 1e-3 and np.max(track.forward[:, 1]) <= 1e-3
    assert track.waterfall_orders[8] == 1.0  # 8 revolutions a window: bins of 1/8 order
    assert track.waterfall_forward.shape == (len(track.time), len(track.waterfall_orders))
    assert np.array_equal(track.waterfall_forward[:, 8], track.forward[:, 0])


@pytest.mark.parametrize("kw", [
    dict(window="blackman"),
    dict(orders=[0.3]),
    dict(per_revolution=4, orders=[2.0]),
    dict(revolutions_per_window=0),
])
def test_order_track_bad_input(kw):
    t = np.linspace(0.0, 10.0, 4000)
    phase = 20 * t
    with pytest.raises(ValueError):
        jeffcott.order_track(t, phase, np.cos(phase), np.sin(phase), **kw)


def test_order_track_of_a_run_up_reads_the_whirl():
    # A one-node rotor (mass 1, stiffness 100, damping 0.2: critical 10 rad/s) without the
    # ring, run up slowly from 5 to 15 rad/s: below the critical the 1x forward whirl is the
    # steady unbalance response at the window's speed, m e W^2 / |k - W^2 + i c W| (measured:
    # within 0.8 %; the free vibration the start leaves is at another order). Beyond it the
    # free vibration the passage leaves, at order 10/W, leaks into the 1x bin.
    M = np.diag([1.0, 1.0, 0.02, 0.02])
    K = np.diag([100.0, 100.0, 60.0, 60.0])
    C = np.diag([0.2, 0.2, 0.01, 0.01])
    me = 0.01
    run = jeffcott.fe_run_up(M, K, C, np.zeros((4, 4)), [0.0, 60.0], [5.0, 15.0], ring_node=0,
                             gap=1.0, ring_stiffness=1.0, ring_damping=0.0,
                             unbalance=[(0, me, 0.0)], layout="lateral4", ring=False)
    assert np.allclose(np.diff(run.phase), 0.5 * (run.speed[1:] + run.speed[:-1]) * np.diff(run.t),
                       rtol=1e-9)
    track = jeffcott.order_track(run.t, run.phase, run.x, run.y, orders=[1.0])
    w = track.speed
    steady = me * w**2 / np.abs(100.0 - w**2 + 0.2j * w)
    away = w < 8.5
    assert away.sum() > 8
    err = np.max(np.abs(track.forward[away, 0] / steady[away] - 1))
    assert err <= 0.01, err
    assert np.max(track.backward[away, 0]) <= 0.02 * np.max(track.forward[away, 0])


def test_revolution_first_order_is_the_steady_response():
    # The one-node rotor damped at 10 % (the start's free vibration gone within seconds) run
    # up slowly, 5 to 15 rad/s in 300 s, without the ring: each revolution's forward 1x whirl
    # is the steady unbalance response at its speed W, m e W^2 H e^{i phase0},
    # H = 1/(k - W^2 + i c W), radius and phase written out, to the quasi-static lag of the
    # ramp (measured: 0.95 % at least 2 rad/s from the critical; 7 % with a 60 s ramp). The
    # order tracking, another algorithm on the same samples (8-revolution Hann windows
    # resampled in the angle), reads the same 1x (measured: within 1.4e-3).
    M = np.diag([1.0, 1.0, 0.02, 0.02])
    K = np.diag([100.0, 100.0, 60.0, 60.0])
    C = np.diag([2.0, 2.0, 0.01, 0.01])
    me, phase0 = 0.01, 0.3
    run = jeffcott.fe_run_up(M, K, C, np.zeros((4, 4)), [0.0, 300.0], [5.0, 15.0], ring_node=0,
                             gap=1.0, ring_stiffness=1.0, ring_damping=0.0,
                             unbalance=[(0, me, phase0)], layout="lateral4", ring=False)
    rev = run.revolutions
    w = rev.speed
    steady = me * w**2 / (100.0 - w**2 + 2.0j * w) * np.exp(1j * phase0)
    got = rev.amplitude_1x * np.exp(1j * rev.phase_1x)
    away = (rev.start > 10.0) & (np.abs(w - 10.0) > 2.0)
    assert away.sum() > 200
    err = np.max(np.abs(got[away] - steady[away]) / np.abs(steady[away]))
    assert err <= 0.015, err
    lag = np.angle(steady[away] * np.exp(-1j * phase0))
    assert lag.min() < -2.5 and lag.max() > -0.5  # the phase sweeps through the critical
    track = jeffcott.order_track(run.t, run.phase, run.x, run.y, orders=[1.0])
    mid = 0.5 * (rev.start + rev.end)
    at = np.interp(track.time, mid, rev.amplitude_1x)
    assert np.max(np.abs(track.forward[:, 0] / at - 1)) <= 5e-3
