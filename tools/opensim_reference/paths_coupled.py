"""Muscle-tendon lengths and moment arms of OpenSim's own gait models, computed by OpenSim
itself at poses whose coupled coordinates come from their `CoordinateCouplerConstraint`s,
for stride's tests.

For each model of `../shared/reference/models/opensim` (NOTICE.md there): 200 poses with
every unlocked independent coordinate uniform in its range (seed 20261208), locked
coordinates at their defaults and every coupled coordinate given by its constraint's
function (evaluated by OpenSim), after which OpenSim assembles the pose (`model.assemble`)
and the coordinate values it ends with are written. Then `muscle.getLength(state)` of
every muscle at every pose, and `muscle.computeMomentArm(state, coordinate)` at every
pose for every muscle and independent coordinate whose moment arm exceeds 1e-6 m at one
of 25 probe poses (OpenSim's moment arm about an independent coordinate moves its coupled
coordinates with it). Written to
`crates/geometry/tests/data/opensim_paths/<tag>_{poses,lengths,moment_arms}.csv` in the
format of `paths.py`; the poses file marks the coupled coordinates in a comment line.

Run from the repository root (see README.md in this folder):

    /work/venv-opensim/bin/python tools/opensim_reference/paths_coupled.py ../shared/reference
"""

import hashlib
import os
import sys

import numpy as np
import opensim as osim

MODELS = [
    ("gait2392", "models/opensim/gait2392_millard2012muscle.osim"),
    ("gait10dof18", "models/opensim/gait10dof18musc.osim"),
    ("rajagopal2016", "models/opensim/Rajagopal2016.osim"),
    ("hamner2010", "models/opensim/FullBodyModel_Hamner2010_v2_0.osim"),
    ("subject01_simbody", "models/opensim/gait2392_pipeline/subject01_simbody.osim"),
    ("gait2d", "models/opensim/moco_example2DWalking/2D_gait.osim"),
]
N_POSES = 200
MA_PROBE = 25  # poses used to find the muscle-coordinate pairs with a moment arm
MA_ZERO = 1e-6  # [m]: pairs whose moment arm stays below this at the probe poses are zero
SEED = 20261208


def couplers(model):
    """(dependent name, independent name, function) of every enforced coupler."""
    out = []
    cs = model.getConstraintSet()
    for i in range(cs.getSize()):
        c = osim.CoordinateCouplerConstraint.safeDownCast(cs.get(i))
        if c is None or not c.get_isEnforced():
            continue
        names = c.getIndependentCoordinateNames()
        assert names.getSize() == 1, f"{c.getName()}: {names.getSize()} independent coordinates"
        out.append((c.getDependentCoordinateName(), names.get(0), c.getFunction()))
    return out


def all_muscles(model):
    """Every muscle of the model, in its force set or in a `<components>` list."""
    out = []
    for c in model.getComponentsList():
        m = osim.Muscle.safeDownCast(c)
        if m is not None:
            out.append(m)
    return out


def sample_pose(coords, coupled, rng):
    """Independent coordinates uniform in their ranges (locked ones at default), rounded to
    6 significant digits, then the coupled ones from their constraint's function."""
    dependent = {d for d, _, _ in coupled}
    q = {}
    for c in coords:
        n = c.getName()
        if n in dependent:
            continue
        v = c.getDefaultValue() if c.get_locked() else rng.uniform(c.getRangeMin(), c.getRangeMax())
        q[n] = float(f"{v:.6g}")
    for d, i, f in coupled:
        x = osim.Vector(1, q[i])
        q[d] = f.calcValue(x)
    return q


def assemble(model, state, coords, q):
    """Sets the pose `q` (name → value), lets OpenSim assemble it, returns the values it
    ends with (model coordinate order)."""
    for c in coords:
        c.setValue(state, q[c.getName()], False)
    model.assemble(state)
    model.realizePosition(state)
    return [c.getValue(state) for c in coords]


def run_model(reference, tag, rel, out_dir):
    path = os.path.join(reference, rel)
    with open(path, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()
    model = osim.Model(path)
    state = model.initSystem()
    cs = model.getCoordinateSet()
    coords = [cs.get(i) for i in range(cs.getSize())]
    names = [c.getName() for c in coords]
    coupled = couplers(model)
    dependent = {d for d, _, _ in coupled}
    rng = np.random.default_rng(SEED)
    poses = []
    for _ in range(N_POSES):
        q = sample_pose(coords, coupled, rng)
        got = assemble(model, state, coords, q)
        for c, v in zip(coords, got):
            n = c.getName()
            assert abs(v - q[n]) <= 1e-6, f"{tag}: assembly moved {n}: {q[n]} -> {v}"
        poses.append(got)
    muscles = all_muscles(model)
    mnames = [m.getName() for m in muscles]
    free = [j for j, c in enumerate(coords) if names[j] not in dependent and not c.get_locked()]
    lengths = []
    for q in poses:
        for c, v in zip(coords, q):
            c.setValue(state, v, False)
        model.realizePosition(state)
        lengths.append([m.getLength(state) for m in muscles])
    big = np.zeros((len(muscles), len(coords)))
    for q in poses[: max(1, len(poses) // MA_PROBE) * MA_PROBE : max(1, len(poses) // MA_PROBE)]:
        for c, v in zip(coords, q):
            c.setValue(state, v, False)
        model.realizePosition(state)
        for i, m in enumerate(muscles):
            for j in free:
                big[i, j] = max(big[i, j], abs(m.computeMomentArm(state, coords[j])))
    pairs = [(i, j) for i in range(len(muscles)) for j in free if big[i, j] > MA_ZERO]
    arms = []
    for k, q in enumerate(poses):
        for c, v in zip(coords, q):
            c.setValue(state, v, False)
        model.realizePosition(state)
        arms.append([k] + [muscles[i].computeMomentArm(state, coords[j]) for i, j in pairs])
    head = f"# OpenSim {osim.__version__}, {rel}, sha256 {digest}\n"
    with open(os.path.join(out_dir, f"{tag}_poses.csv"), "w") as f:
        f.write(head + "# coordinate values [rad or m], one pose per row (assembled by OpenSim)\n")
        f.write("# coupled: " + " ".join(f"{d}={i}" for d, i, _ in coupled) + "\n")
        f.write(",".join(names) + "\n")
        for q in poses:
            f.write(",".join(f"{v:.10g}" for v in q) + "\n")
    with open(os.path.join(out_dir, f"{tag}_lengths.csv"), "w") as f:
        f.write(head + "# muscle-tendon length [mm] (muscle.getLength), one pose per row\n")
        f.write(",".join(mnames) + "\n")
        for l in lengths:
            f.write(",".join(f"{v * 1e3:.4f}" for v in l) + "\n")
    with open(os.path.join(out_dir, f"{tag}_moment_arms.csv"), "w") as f:
        f.write(head + "# moment arm [mm] (muscle.computeMomentArm) of every nonzero pair, every pose\n")
        f.write("pose," + ",".join(f"{mnames[i]}:{names[j]}" for i, j in pairs) + "\n")
        for row in arms:
            f.write(str(row[0]) + "," + ",".join(f"{v * 1e3:.4f}" for v in row[1:]) + "\n")
    print(f"{tag}: {len(poses)} poses, {len(muscles)} muscles, {len(pairs)} moment-arm pairs, "
          f"{len(coupled)} couplers", flush=True)


def main():
    reference = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "../shared/reference")
    out_dir = os.path.abspath("crates/geometry/tests/data/opensim_paths")
    os.makedirs(out_dir, exist_ok=True)
    only = sys.argv[2:] or [t for t, _ in MODELS]
    # OpenSim writes opensim.log into the working folder: keep it out of the repository.
    os.chdir("/tmp")
    osim.Logger.setLevelString("error")
    for tag, rel in MODELS:
        if tag in only:
            run_model(reference, tag, rel, out_dir)


if __name__ == "__main__":
    main()
