"""A small model exercising OpenSim's wrapping over cylinders and spheres (quadrants,
point ranges, two wraps on one path, points inside the object), and its muscle lengths
and moment arms computed by OpenSim, for stride's tests.

Writes `crates/geometry/tests/data/wrap_model.osim` (built with the OpenSim API) and
`crates/geometry/tests/data/opensim_paths/wrap_model_{poses,lengths,moment_arms}.csv`
in the format of `paths.py`. Run from the repository root:

    /work/venv-opensim/bin/python tools/opensim_reference/paths_wrap.py
"""

import math
import os
import sys

import numpy as np
import opensim as osim

V = osim.Vec3


def pin(name, parent, child, loc, orient):
    """A PinJoint rotating about the z axis of its frame (oriented by `orient`)."""
    j = osim.PinJoint(name, parent, V(*loc), V(*orient), child, V(0, 0, 0), V(*orient))
    return j


def wrap(cls, name, body, translation, rotation, quadrant, **dims):
    w = getattr(osim, cls)()
    w.setName(name)
    w.set_translation(V(*translation))
    w.set_xyz_body_rotation(V(*rotation))
    w.set_quadrant(quadrant)
    for k, v in dims.items():
        getattr(w, f"set_{k}")(v)
    body.addWrapObject(w)
    return w


def muscle(model, name, points, wraps, method=None):
    m = osim.Thelen2003Muscle(name, 1000.0, 0.1, 0.2, 0.0)
    for k, (body, loc) in enumerate(points):
        m.addNewPathPoint(f"{name}_p{k + 1}", body, V(*loc))
    for w, rng in wraps:
        m.updGeometryPath().addPathWrap(w)
        pw = m.updGeometryPath().updWrapSet().get(m.getGeometryPath().getWrapSet().getSize() - 1)
        pw.set_range(0, rng[0])
        pw.set_range(1, rng[1])
        if method is not None:
            pw.setMethod(method)
    model.addForce(m)


def skeleton(name):
    """Ground, a welded base, `link` on the pin `q_swing` and `arm` on the pin `q_tilt`."""
    model = osim.Model()
    model.setName(name)
    ground = model.getGround()
    base = osim.Body("base", 1.0, V(0, 0, 0), osim.Inertia(0.01, 0.01, 0.01))
    link = osim.Body("link", 1.0, V(0, 0, 0), osim.Inertia(0.01, 0.01, 0.01))
    arm = osim.Body("arm", 1.0, V(0, 0, 0), osim.Inertia(0.01, 0.01, 0.01))
    model.addBody(base)
    model.addBody(link)
    model.addBody(arm)
    # A welded base, so that the swing joint is not attached to the ground (stride's random
    # fitting poses keep the coordinates of ground joints at zero).
    model.addJoint(osim.WeldJoint("base_weld", ground, V(0, 0, 0), V(0, 0, 0), base, V(0, 0, 0), V(0, 0, 0)))
    j1 = pin("swing", base, link, (0, 0, 0), (0, 0, 0))
    j2 = pin("tilt", link, arm, (0, 0, 0), (0, math.pi / 2, 0))
    model.addJoint(j1)
    model.addJoint(j2)
    for j, lo, hi in ((j1, -2.5, 2.5), (j2, -0.8, 0.8)):
        c = j.updCoordinate()
        c.setRangeMin(lo)
        c.setRangeMax(hi)
    j1.updCoordinate().setName("q_swing")
    j2.updCoordinate().setName("q_tilt")
    return model, ground, arm


def build():
    model, ground, arm = skeleton("wrap_model")
    cyl = wrap("WrapCylinder", "cyl", ground, (0, 0, 0), (0, 0, 0), "all", radius=0.04, length=0.3)
    cyl_ny = wrap("WrapCylinder", "cyl_ny", ground, (0, 0, 0.01), (0.2, 0, 0), "-y", radius=0.04, length=0.3)
    cyl_px = wrap("WrapCylinder", "cyl_px", arm, (0.1, 0, 0), (0, 0.3, 0.1), "+x", radius=0.03, length=0.12)
    sph = wrap("WrapSphere", "sph", ground, (0, 0.01, 0), (0, 0, 0), "all", radius=0.05)
    sph_y = wrap("WrapSphere", "sph_y", ground, (0.01, 0, 0), (0, 0, 0.3), "+y", radius=0.05)
    sph2 = wrap("WrapSphere", "sph2", arm, (0.12, 0.02, 0), (0, 0, 0), "all", radius=0.025)
    g, a = ground, arm
    muscle(model, "cyl_all", [(g, (-0.15, 0.06, 0.03)), (a, (0.15, 0.05, -0.02))], [(cyl, (-1, -1))])
    muscle(model, "cyl_neg_y", [(g, (-0.15, -0.02, 0.02)), (a, (0.16, 0.03, 0.04))], [(cyl_ny, (-1, -1))])
    muscle(model, "cyl_on_arm", [(g, (0.05, 0.12, 0.0)), (a, (0.2, -0.05, 0.01))], [(cyl_px, (-1, -1))])
    muscle(model, "sph_all", [(g, (-0.14, 0.05, -0.02)), (a, (0.15, 0.04, 0.03))], [(sph, (-1, -1))])
    muscle(model, "sph_pos_y", [(g, (-0.15, 0.0, 0.04)), (a, (0.14, 0.02, -0.03))], [(sph_y, (-1, -1))])
    muscle(
        model,
        "three_points",
        [(g, (-0.2, 0.08, 0.0)), (g, (-0.1, 0.07, 0.01)), (a, (0.1, 0.05, 0.0)), (a, (0.2, 0.02, 0.0))],
        [(cyl, (2, 3))],
    )
    muscle(
        model,
        "two_wraps",
        [(g, (-0.15, 0.05, 0.0)), (a, (0.22, 0.03, 0.01))],
        [(cyl, (-1, -1)), (sph2, (-1, -1))],
    )
    model.finalizeConnections()
    return model


def write_reference(model, tag, seed=7, n_poses=500, every=5):
    """Writes `model` as `<tag>.osim` and its reference CSVs (run from the repository root)."""
    out = os.path.abspath("crates/geometry/tests/data")
    os.makedirs(os.path.join(out, "opensim_paths"), exist_ok=True)
    cwd = os.getcwd()
    os.chdir("/tmp")
    model.initSystem()
    path = os.path.join(out, f"{tag}.osim")
    model.printToXML(path)
    model = osim.Model(path)
    state = model.initSystem()
    cs = model.getCoordinateSet()
    coords = [cs.get(i) for i in range(cs.getSize())]
    rng = np.random.default_rng(seed)
    poses = [[float(f"{rng.uniform(c.getRangeMin(), c.getRangeMax()):.6g}") for c in coords] for _ in range(n_poses)]
    ms = model.getMuscles()
    muscles = [ms.get(i) for i in range(ms.getSize())]
    script = os.path.basename(sys.argv[0])
    head = f"# OpenSim {osim.__version__}, {tag}.osim (tools/opensim_reference/{script})\n"
    d = os.path.join(out, "opensim_paths")
    with open(os.path.join(d, f"{tag}_poses.csv"), "w") as f:
        f.write(head + "# coordinate values [rad or m], one pose per row\n")
        f.write(",".join(c.getName() for c in coords) + "\n")
        for q in poses:
            f.write(",".join(f"{v:.6g}" for v in q) + "\n")
    lf = open(os.path.join(d, f"{tag}_lengths.csv"), "w")
    af = open(os.path.join(d, f"{tag}_moment_arms.csv"), "w")
    lf.write(head + "# muscle-tendon length [mm] (muscle.getLength), one pose per row\n")
    lf.write(",".join(m.getName() for m in muscles) + "\n")
    af.write(head + f"# moment arm [mm] (muscle.computeMomentArm) of every pair, every {every}th pose\n")
    af.write("pose," + ",".join(f"{m.getName()}:{c.getName()}" for m in muscles for c in coords) + "\n")
    for k, q in enumerate(poses):
        for c, v in zip(coords, q):
            c.setValue(state, v, False)
        model.realizePosition(state)
        lf.write(",".join(f"{m.getLength(state) * 1e3:.4f}" for m in muscles) + "\n")
        if k % every == 0:
            arms = [m.computeMomentArm(state, c) * 1e3 for m in muscles for c in coords]
            af.write(f"{k}," + ",".join(f"{v:.4f}" for v in arms) + "\n")
    lf.close()
    af.close()
    os.chdir(cwd)
    print(f"{tag}: {len(poses)} poses, {len(muscles)} muscles")


def main():
    osim.Logger.setLevelString("error")
    write_reference(build(), "wrap_model")


if __name__ == "__main__":
    main()
