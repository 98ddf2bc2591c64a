"""A small model with a coupled coordinate (a kneecap whose angle follows the knee through
a nonlinear `CoordinateCouplerConstraint`) and its muscle lengths and moment arms computed
by OpenSim, for stride's tests of coupled coordinates in the path geometry and in
`stride model paths`.

Writes `crates/geometry/tests/data/coupled_model.osim` (built with the OpenSim API) and
`crates/geometry/tests/data/opensim_paths/coupled_model_{poses,lengths,moment_arms}.csv`
with `paths_coupled.py`. Run from the repository root:

    python3 tools/opensim_reference/paths_coupled_small.py
"""

import os
import sys

import opensim as osim

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import paths_coupled  # noqa: E402

V = osim.Vec3


def body(model, name):
    b = osim.Body(name, 1.0, V(0, 0, 0), osim.Inertia(0.01, 0.01, 0.01))
    model.addBody(b)
    return b


def pin(model, name, parent, child, loc, coord, lo, hi):
    j = osim.PinJoint(name, parent, V(*loc), V(0, 0, 0), child, V(0, 0, 0), V(0, 0, 0))
    model.addJoint(j)
    c = j.updCoordinate()
    c.setName(coord)
    c.setRangeMin(lo)
    c.setRangeMax(hi)
    return c


def muscle(model, name, points):
    m = osim.Thelen2003Muscle(name, 1000.0, 0.1, 0.2, 0.0)
    for k, (b, loc) in enumerate(points):
        m.addNewPathPoint(f"{name}_p{k + 1}", b, V(*loc))
    model.addForce(m)


def build():
    """Ground, a welded base, `thigh` on the pin `q_hip`, `shank` on the pin `q_knee` and
    `cap` on the pin `q_cap` with `q_cap = f(q_knee)` (a spline)."""
    model = osim.Model()
    model.setName("coupled_model")
    ground = model.getGround()
    base = body(model, "base")
    thigh = body(model, "thigh")
    shank = body(model, "shank")
    cap = body(model, "cap")
    model.addJoint(osim.WeldJoint("base_weld", ground, V(0, 0, 0), V(0, 0, 0), base, V(0, 0, 0), V(0, 0, 0)))
    pin(model, "hip", base, thigh, (0, 0, 0), "q_hip", -1.0, 1.0)
    pin(model, "knee", thigh, shank, (0, -0.4, 0), "q_knee", -1.8, 0.2)
    pin(model, "cap_joint", thigh, cap, (0.04, -0.38, 0), "q_cap", -99999.9, 99999.9)
    f = osim.SimmSpline()
    for x, y in ((-2.0, -0.9), (-1.2, -0.7), (-0.5, -0.2), (0.0, 0.05), (0.5, 0.1)):
        f.addPoint(x, y)
    cc = osim.CoordinateCouplerConstraint()
    cc.setName("cap_follows_knee")
    names = osim.ArrayStr()
    names.append("q_knee")
    cc.setIndependentCoordinateNames(names)
    cc.setDependentCoordinateName("q_cap")
    cc.setFunction(f)
    model.addConstraint(cc)
    muscle(model, "over_cap", [(base, (0.05, -0.1, 0.01)), (cap, (0.03, 0.02, 0.0)), (shank, (0.03, -0.1, 0.0))])
    muscle(model, "to_cap", [(thigh, (0.04, -0.2, 0.0)), (cap, (0.02, -0.01, 0.01))])
    muscle(model, "behind", [(thigh, (-0.03, -0.1, 0.0)), (shank, (-0.03, -0.12, 0.0))])
    model.finalizeConnections()
    return model


def main():
    osim.Logger.setLevelString("error")
    data = os.path.abspath("crates/geometry/tests/data")
    model = build()
    cwd = os.getcwd()
    os.chdir("/tmp")
    model.initSystem()
    model.printToXML(os.path.join(data, "coupled_model.osim"))
    paths_coupled.run_model(data, "coupled_model", "coupled_model.osim", os.path.join(data, "opensim_paths"))
    os.chdir(cwd)


if __name__ == "__main__":
    main()
