"""A small model exercising OpenSim's wrapping over ellipsoids (the three path-wrap
methods, quadrants, an ellipsoid on a moving body, a point range), and its muscle lengths
and moment arms computed by OpenSim, for stride's tests.

Writes `crates/geometry/tests/data/wrap_ellipsoid_model.osim` (built with the OpenSim
API) and `crates/geometry/tests/data/opensim_paths/wrap_ellipsoid_model_*.csv` in the
format of `paths.py`. Run from the repository root:

    /work/venv-opensim/bin/python tools/opensim_reference/paths_wrap_ellipsoid.py
"""

import opensim as osim

from paths_wrap import muscle, skeleton, wrap, write_reference


def build():
    model, g, a = skeleton("wrap_ellipsoid_model")
    ell = wrap("WrapEllipsoid", "ell", g, (0, 0.005, 0), (0.3, 0.2, 0.1), "all", dimensions=osim.Vec3(0.05, 0.035, 0.06))
    ell_y = wrap("WrapEllipsoid", "ell_y", g, (0.01, 0, 0), (0, 0, 0.3), "+y", dimensions=osim.Vec3(0.045, 0.04, 0.07))
    ell_nz = wrap("WrapEllipsoid", "ell_nz", g, (0, 0, 0.01), (0.1, 0, 0), "-z", dimensions=osim.Vec3(0.05, 0.03, 0.05))
    ell_arm = wrap("WrapEllipsoid", "ell_arm", a, (0.1, 0.01, 0), (0, 0.2, 0.1), "all", dimensions=osim.Vec3(0.03, 0.025, 0.04))
    muscle(model, "ell_hybrid", [(g, (-0.15, 0.06, 0.03)), (a, (0.15, 0.05, -0.02))], [(ell, (-1, -1))])
    muscle(model, "ell_midpoint", [(g, (-0.14, 0.05, -0.02)), (a, (0.15, 0.04, 0.03))], [(ell, (-1, -1))], osim.PathWrap.midpoint)
    muscle(model, "ell_axial", [(g, (-0.15, 0.0, 0.04)), (a, (0.14, 0.02, -0.03))], [(ell, (-1, -1))], osim.PathWrap.axial)
    muscle(model, "ell_pos_y", [(g, (-0.15, 0.0, 0.04)), (a, (0.14, 0.02, -0.03))], [(ell_y, (-1, -1))])
    muscle(model, "ell_neg_z", [(g, (-0.15, -0.02, 0.02)), (a, (0.16, 0.03, 0.04))], [(ell_nz, (-1, -1))])
    muscle(model, "ell_on_arm", [(g, (0.05, 0.12, 0.0)), (a, (0.2, -0.05, 0.01))], [(ell_arm, (-1, -1))])
    muscle(
        model,
        "ell_three_points",
        [(g, (-0.2, 0.08, 0.0)), (g, (-0.1, 0.07, 0.01)), (a, (0.1, 0.05, 0.0)), (a, (0.2, 0.02, 0.0))],
        [(ell, (2, 3))],
    )
    model.finalizeConnections()
    return model


def main():
    osim.Logger.setLevelString("error")
    write_reference(build(), "wrap_ellipsoid_model", seed=11)


if __name__ == "__main__":
    main()
