"""A small model exercising OpenSim's wrapping over tori (a path through the hole, a path
beside the ring, a quadrant, a torus on the moving body, an inactive torus) and paths
with two wraps (two cylinders; a torus and a cylinder), and its muscle lengths and moment
arms computed by OpenSim, for stride's tests.

Writes `crates/geometry/tests/data/wrap_torus_model.osim` (built with the OpenSim API) and
`crates/geometry/tests/data/opensim_paths/wrap_torus_model_*.csv` in the format of
`paths.py`. Run from the repository root:

    /work/venv-opensim/bin/python tools/opensim_reference/paths_wrap_torus.py
"""

import math

import opensim as osim

from paths_wrap import muscle, skeleton, wrap, write_reference

AXIS_X = (0, math.pi / 2, 0)  # the torus axis (z of its frame) along the body's x axis


def build():
    model, g, a = skeleton("wrap_torus_model")
    tor = wrap("WrapTorus", "tor", g, (0, 0.04, 0), AXIS_X, "all", inner_radius=0.012, outer_radius=0.04)
    tor_y = wrap("WrapTorus", "tor_y", g, (0.01, 0.03, 0.01), (0.1, math.pi / 2, 0), "+y", inner_radius=0.01, outer_radius=0.045)
    tor_arm = wrap("WrapTorus", "tor_arm", a, (0.1, 0, 0), AXIS_X, "all", inner_radius=0.01, outer_radius=0.035)
    tor_off = wrap("WrapTorus", "tor_off", g, (0, 0.04, 0), AXIS_X, "all", inner_radius=0.012, outer_radius=0.04)
    tor_off.set_active(False)
    cyl_a = wrap("WrapCylinder", "cyl_a", g, (0, 0, 0), (0, 0, 0), "all", radius=0.03, length=0.3)
    cyl_b = wrap("WrapCylinder", "cyl_b", a, (0.12, 0.0, 0), (0, 0, 0.2), "+y", radius=0.02, length=0.1)
    cyl_ny = wrap("WrapCylinder", "cyl_ny", g, (0, 0, 0.01), (0.2, 0, 0), "-y", radius=0.04, length=0.3)
    cyl_px = wrap("WrapCylinder", "cyl_px", a, (0.1, 0, 0), (0, 0.3, 0.1), "+x", radius=0.03, length=0.12)
    far = wrap("WrapSphere", "far", g, (5, 5, 5), (0, 0, 0), "all", radius=0.01)
    muscle(model, "tor_hole", [(g, (-0.15, 0.05, 0.0)), (a, (0.2, 0.03, 0.01))], [(tor, (-1, -1))])
    muscle(model, "tor_beside", [(g, (-0.15, 0.12, 0.0)), (a, (0.2, 0.1, 0.0))], [(tor, (-1, -1))])
    muscle(model, "tor_pos_y", [(g, (-0.15, 0.04, 0.02)), (a, (0.2, 0.02, 0.0))], [(tor_y, (-1, -1))])
    muscle(model, "tor_on_arm", [(g, (-0.15, 0.0, 0.0)), (a, (0.2, 0.0, 0.005))], [(tor_arm, (-1, -1))])
    muscle(model, "tor_inactive", [(g, (-0.15, 0.05, 0.0)), (a, (0.2, 0.03, 0.01))], [(tor_off, (-1, -1))])
    muscle(model, "two_cylinders", [(g, (-0.15, 0.05, 0.0)), (a, (0.22, 0.03, 0.01))], [(cyl_a, (-1, -1)), (cyl_b, (-1, -1))])
    # A second wrap that never wraps: the cylinder's tangent points slide as on any path
    # with two wraps (on the arm, towards tangency without converging at some poses).
    muscle(model, "cyl_neg_y_slid", [(g, (-0.15, -0.02, 0.02)), (a, (0.16, 0.03, 0.04))], [(cyl_ny, (-1, -1)), (far, (-1, -1))])
    muscle(model, "cyl_on_arm_slid", [(g, (0.05, 0.12, 0.0)), (a, (0.2, -0.05, 0.01))], [(cyl_px, (-1, -1)), (far, (-1, -1))])
    muscle(model, "torus_cylinder", [(g, (-0.15, 0.05, 0.0)), (a, (0.22, 0.03, 0.01))], [(tor, (-1, -1)), (cyl_b, (-1, -1))])
    model.finalizeConnections()
    model.finalizeFromProperties()
    swing = model.getCoordinateSet().get("q_swing")
    swing.setRangeMin(-1.2)
    swing.setRangeMax(1.2)
    return model


def main():
    osim.Logger.setLevelString("error")
    write_reference(build(), "wrap_torus_model", seed=13)


if __name__ == "__main__":
    main()
