"""ROSS's rotor_example (7 nodes, 42 DOF) with bearings whose coefficients follow the speed
(anisotropic, symmetric cross terms: not circulatory),
exported by ROSS itself (`rotor.save_mat(file, speed=W)`) at three speeds: the input of
`run_up --fe --fe-bearing-mat SPEED:FILE` (tests/suite/examples/run_up_cli.rs)."""
import numpy as np
import ross as rs

base = rs.rotor_example()
speeds = np.array([0.0, 200.0, 400.0])  # rad/s: the bearings' table
bearings = [
    rs.BearingElement(n=b.n, kxx=[1e6, 1.6e6, 2.6e6], kyy=[0.8e6, 1.3e6, 2.2e6],
                      kxy=[0.0, 1e5, 3e5], kyx=[0.0, 1e5, 3e5],
                      cxx=[40.0, 80.0, 150.0], cyy=[30.0, 60.0, 120.0], frequency=speeds)
    for b in base.bearing_elements
]
rotor = rs.Rotor(base.shaft_elements, base.disk_elements, bearings)
for w in (100.0, 150.0, 200.0):
    rotor.save_mat(f"rotor_example_bearings_{int(w)}rads.mat", speed=w)
    K = rotor.K(w, w)
    print(w, K[0, 0], len(rotor.nodes))
