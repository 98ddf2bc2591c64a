"""Muscle-tendon lengths and moment arms computed by OpenSim itself, for stride's tests.

For each model: 500 poses (coordinates uniform in their ranges, then frames of walking
motions where the model has their coordinates), OpenSim's `muscle.getLength(state)` at
every pose and `muscle.computeMomentArm(state, coordinate)` at every tenth pose for every
muscle-coordinate pair whose moment arm is not zero. Written compactly to
`crates/geometry/tests/data/opensim_paths/<tag>_{poses,lengths,moment_arms}.csv`.

Run from the repository root (see README.md in this folder):

    /work/venv-opensim/bin/python tools/opensim_reference/paths.py ../shared/reference
"""

import hashlib
import math
import os
import sys

import numpy as np
import opensim as osim

MODELS = [
    ("subject1_v2", "models/subject1_v2.osim"),
    ("subject1", "models/subject1.osim"),
    ("hamner", "models/Hamner_modified_scaled.osim"),
    ("falisse2022", "models/predsim/Falisse_et_al_2022.osim"),
    ("gait1018", "models/predsim/gait1018.osim"),
    ("dhondt2024", "models/predsim/DHondt_et_al_2024_4seg.osim"),
]
MOTIONS = ["experimental/gait_1_ik.mot", "experimental/ik_walking_full_cycle.mot"]
N_POSES = 500
N_UNIFORM = 300
MA_EVERY = 10
MA_PROBE = 25  # poses used to find the muscle-coordinate pairs with a moment arm
MA_ZERO = 1e-6  # [m]: pairs whose moment arm stays below this at the probe poses are zero


def sig6(x):
    """Round to 6 significant digits (the poses are evaluated at the rounded values)."""
    return float(f"{x:.6g}")


def read_motion(path):
    """Columns and rows (list of dicts) of an OpenSim .mot file; degrees converted later."""
    with open(path) as f:
        lines = f.read().splitlines()
    in_degrees = True
    i = 0
    while lines[i].strip().lower() != "endheader":
        if lines[i].startswith("inDegrees="):
            in_degrees = lines[i].split("=")[1].strip().lower() == "yes"
        i += 1
    cols = lines[i + 1].split()
    rows = [dict(zip(cols, map(float, l.split()))) for l in lines[i + 2 :] if l.strip()]
    return rows, in_degrees


def poses_for(model, reference, rng):
    cs = model.getCoordinateSet()
    coords = [cs.get(i) for i in range(cs.getSize())]
    names = [c.getName() for c in coords]
    uniform = []
    for _ in range(N_UNIFORM):
        q = []
        for c in coords:
            if c.get_locked():
                q.append(c.getDefaultValue())
            else:
                q.append(rng.uniform(c.getRangeMin(), c.getRangeMax()))
        uniform.append(q)
    motion = []
    for m in MOTIONS:
        rows, deg = read_motion(os.path.join(reference, m))
        for r in rows:
            q = []
            for c in coords:
                n = c.getName()
                if n in r and not c.get_locked():
                    rot = c.getMotionType() == 1  # Rotational
                    q.append(math.radians(r[n]) if (deg and rot) else r[n])
                else:
                    q.append(c.getDefaultValue())
            motion.append(q)
    n_motion = N_POSES - N_UNIFORM
    idx = np.linspace(0, len(motion) - 1, n_motion).round().astype(int)
    poses = uniform + [motion[i] for i in idx]
    return names, coords, [[sig6(v) for v in q] for q in poses]


def set_pose(model, state, coords, q):
    for c, v in zip(coords, q):
        c.setValue(state, v, False)
    model.realizePosition(state)


def run_model(reference, tag, rel, out_dir):
    path = os.path.join(reference, rel)
    with open(path, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()
    model = osim.Model(path)
    state = model.initSystem()
    names, coords, poses = poses_for(model, reference, np.random.default_rng(20261206))
    ms = model.getMuscles()
    muscles = [ms.get(i) for i in range(ms.getSize())]
    mnames = [m.getName() for m in muscles]
    lengths = []
    for q in poses:
        set_pose(model, state, coords, q)
        lengths.append([m.getLength(state) for m in muscles])
    pairs = []
    probe = poses[:: max(1, len(poses) // MA_PROBE)][:MA_PROBE]
    big = np.zeros((len(muscles), len(coords)))
    for q in probe:
        set_pose(model, state, coords, q)
        for i, m in enumerate(muscles):
            for j, c in enumerate(coords):
                big[i, j] = max(big[i, j], abs(m.computeMomentArm(state, c)))
    pairs = [(i, j) for i in range(len(muscles)) for j in range(len(coords)) if big[i, j] > MA_ZERO]
    arms = []
    for k in range(0, len(poses), MA_EVERY):
        set_pose(model, state, coords, poses[k])
        arms.append([k] + [muscles[i].computeMomentArm(state, coords[j]) for i, j in pairs])
    head = f"# OpenSim {osim.__version__}, {rel}, sha256 {digest}\n"
    with open(os.path.join(out_dir, f"{tag}_poses.csv"), "w") as f:
        f.write(head + "# coordinate values [rad or m], one pose per row\n")
        f.write(",".join(names) + "\n")
        for q in poses:
            f.write(",".join(f"{v:.6g}" for v in q) + "\n")
    with open(os.path.join(out_dir, f"{tag}_lengths.csv"), "w") as f:
        f.write(head + "# muscle-tendon length [mm] (muscle.getLength), one pose per row\n")
        f.write(",".join(mnames) + "\n")
        for l in lengths:
            f.write(",".join(f"{v * 1e3:.3f}" for v in l) + "\n")
    with open(os.path.join(out_dir, f"{tag}_moment_arms.csv"), "w") as f:
        f.write(head + "# moment arm [mm] (muscle.computeMomentArm) of every nonzero pair\n")
        f.write("pose," + ",".join(f"{mnames[i]}:{names[j]}" for i, j in pairs) + "\n")
        for row in arms:
            f.write(str(row[0]) + "," + ",".join(f"{v * 1e3:.3f}" for v in row[1:]) + "\n")
    print(f"{tag}: {len(poses)} poses, {len(muscles)} muscles, {len(pairs)} moment-arm pairs")


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
