"""Check a stride result folder with OpenSim 4 (and Moco): the files open as they are, and
OpenSim's own inverse dynamics reproduces the folder's joint torques.

Usage:  python check_result_folder.py <result folder>   (OpenSim 4.6 Python bindings)

Prints one JSON object on stdout and exits with status 1 when a check fails:
  model_loads          model.osim loads and initialises;
  states_are_paths     every column of states.sto (read as a TimeSeriesTable) is a state
                       variable path of that model;
  controls_are_paths   every column of controls.sto is an actuator path of that model;
  moco_trajectory      trajectory.sto reads as a MocoTrajectory with the states, controls and
                       an acceleration (derivative) per coordinate;
  external_loads       grf.xml (with grf.mot) loads as ExternalLoads with two forces;
  inverse_dynamics     per coordinate, the largest difference over the cycle between
                       OpenSim's InverseDynamicsSolver and joint_torques.csv, as a fraction
                       of that torque's range over the cycle. At every sample of
                       trajectory.sto the solver gets the model (model.osim, every model
                       force off, so only gravity, inertia and the ground reactions act, with
                       grf.mot applied through grf.xml), the coordinate values and speeds,
                       and the accelerations the file holds as Moco derivatives
                       (`/jointset/<joint>/<coordinate>/accel`). Within 5 % passes.
  inverse_dynamics_tool
                       the same comparison with OpenSim's InverseDynamicsTool, which takes
                       the accelerations from splines through motion.mot instead. Reported,
                       not checked: the collocation's accelerations jump between mesh
                       intervals at heel strike, which no spline through the samples
                       follows. The cycle is periodic: the motion and the ground reactions
                       are extended by one cycle before and after it (forward position
                       shifted by the stride) so that the tool's splines have no end
                       effects, and the tool's torques are compared on the middle cycle.
  id_setup_file        the same comparison for the folder's own id_setup.xml run as a setup
                       file (`opensim-cmd run-tool id_setup.xml` when opensim-cmd is on the
                       PATH, else an InverseDynamicsTool constructed from the file, which is
                       what run-tool does), on a copy of the files so that the folder is not
                       written to. Reported, not checked: the cycle is not extended, so the
                       tool's splines have end effects at its first and last samples, and the
                       heel strikes differ as above; the worst fraction over all samples and
                       away from the heel strikes are given.
  center_of_pressure   per foot, the largest horizontal distance [m] of the centre of
                       pressure in grf.mot from the region under that foot (the
                       bounding rectangle of its contact spheres' centres in ground, grown
                       by their radius) over the samples where the foot carries more than
                       20 N; within 1 cm passes.
"""

import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

import opensim as osim

CHECKED = ["hip_flexion", "hip_adduction", "hip_rotation", "knee_angle", "ankle_angle",
           "subtalar_angle"]
LUMBAR = ["lumbar_extension", "lumbar_bending", "lumbar_rotation"]
TOLERANCE = 0.05
COP_TOLERANCE = 0.01  # m
LOADED = 20.0  # N


def read_storage(path):
    with open(path) as f:
        lines = f.read().splitlines()
    end = lines.index("endheader")
    header = lines[:end]
    labels = lines[end + 1].split("\t")
    rows = [[float(v) for v in l.split("\t")] for l in lines[end + 2:] if l.strip()]
    return header, labels, rows


def write_storage(path, header, labels, rows):
    with open(path, "w") as f:
        for h in header:
            if h.startswith("nRows="):
                h = f"nRows={len(rows)}"
            f.write(h + "\n")
        f.write("endheader\n" + "\t".join(labels) + "\n")
        for r in rows:
            f.write("\t".join(repr(v) for v in r) + "\n")


def tile(rows, period, shifts):
    """Rows of three periods: before, the cycle, after; `shifts` maps a column to the
    distance it advances per period."""
    out = []
    for k in (-1, 0, 1):
        for r in rows:
            r = list(r)
            r[0] += k * period
            for c, d in shifts.items():
                r[c] += k * d
            out.append(r)
    return out


def value_at(rows, col, t):
    """Column `col` of the storage row whose time is nearest to `t`."""
    return min(rows, key=lambda r: abs(r[0] - t))[col]


def center_of_pressure(folder, model):
    """Per foot, the largest horizontal distance [m] of its centre of pressure from the
    rectangle under its contact spheres while it carries load."""
    _, ml, mrows = read_storage(os.path.join(folder, "motion.mot"))
    _, gl, grows = read_storage(os.path.join(folder, "grf.mot"))
    state = model.initSystem()
    coords = model.getCoordinateSet()
    columns = [(coords.get(i), ml.index(coords.get(i).getName()))
               for i in range(coords.getSize()) if coords.get(i).getName() in ml]
    spheres = {"r": [], "l": []}
    for i in range(model.getContactGeometrySet().getSize()):
        g = model.getContactGeometrySet().get(i)
        sphere = osim.ContactSphere.safeDownCast(g)
        side = g.getFrame().getName()[-1]
        if sphere is not None and side in spheres:
            spheres[side].append(sphere)
    result = {}
    for side, group in spheres.items():
        worst, loaded = 0.0, 0
        fy = gl.index(f"{side}_ground_force_vy")
        px, pz = gl.index(f"{side}_ground_force_px"), gl.index(f"{side}_ground_force_pz")
        for g in grows:
            if g[fy] <= LOADED:
                continue
            loaded += 1
            m = min(mrows, key=lambda r: abs(r[0] - g[0]))
            for c, k in columns:
                rotational = c.getMotionType() == 1
                c.setValue(state, math.radians(m[k]) if rotational else m[k], False)
            model.realizePosition(state)
            centres = [s.getFrame().findStationLocationInGround(state, s.get_location())
                       for s in group]
            r = max(s.getRadius() for s in group)
            xs = [c.get(0) for c in centres]
            zs = [c.get(2) for c in centres]
            dx = max(min(xs) - r - g[px], g[px] - max(xs) - r, 0.0)
            dz = max(min(zs) - r - g[pz], g[pz] - max(zs) - r, 0.0)
            worst = max(worst, math.hypot(dx, dz))
        result[side] = {"loaded_samples": loaded, "max_distance_outside": worst}
    return result


def u_index(model, state):
    """Index in the state's U vector of every coordinate's speed, by coordinate name."""
    coords = model.getCoordinateSet()
    nu = state.getNU()
    index = {}
    for i in range(coords.getSize()):
        c = coords.get(i)
        state.setU(osim.Vector(nu, 0.0))
        c.setSpeedValue(state, 1.0)
        u = state.getU()
        index[c.getName()] = next(k for k in range(nu) if u.get(k) == 1.0)
    return index


def solver_inverse_dynamics(folder, model_path):
    """Per coordinate, OpenSim's InverseDynamicsSolver at the samples of trajectory.sto
    (values, speeds and the accelerations written as Moco derivatives) against
    joint_torques.csv."""
    model = osim.Model(model_path)
    forces = model.getForceSet()
    for i in range(forces.getSize()):
        forces.get(i).set_appliesForce(False)
    loads = osim.ExternalLoads(os.path.join(folder, "grf.xml"), True)
    loads.setDataFileName(os.path.join(folder, "grf.mot"))
    model.addModelComponent(loads)
    state = model.initSystem()
    index = u_index(model, state)
    coords = model.getCoordinateSet()
    _, labels, rows = read_storage(os.path.join(folder, "trajectory.sto"))
    paths = {}
    for i in range(coords.getSize()):
        c = coords.get(i)
        base = f"/jointset/{c.getJoint().getName()}/{c.getName()}"
        paths[c.getName()] = (c, labels.index(base + "/value"), labels.index(base + "/speed"),
                              labels.index(base + "/accel"))
    solver = osim.InverseDynamicsSolver(model)
    nu = state.getNU()
    theirs = {name: [] for name in paths}
    for r in rows:
        state.setTime(r[0])
        udot = osim.Vector(nu, 0.0)
        for name, (c, q, u, a) in paths.items():
            c.setValue(state, r[q], False)
            c.setSpeedValue(state, r[u])
            udot.set(index[name], r[a])
        model.realizeVelocity(state)
        tau = solver.solve(state, udot)
        for name in paths:
            theirs[name].append(tau.get(index[name]))
    with open(os.path.join(folder, "joint_torques.csv")) as f:
        table = list(csv.reader(f))
    names = [h.split(" [")[0] for h in table[0]]
    ref = [[float(v) for v in r] for r in table[1:]]
    if len(ref) != len(rows):
        raise RuntimeError(f"trajectory.sto has {len(rows)} samples, joint_torques.csv {len(ref)}")
    result = {}
    for name in [f"{c}_{s}" for c in CHECKED for s in "rl"] + LUMBAR:
        if name not in names or name not in theirs:
            continue
        ours = [r[names.index(name)] for r in ref]
        diff = max(abs(a - b) for a, b in zip(ours, theirs[name]))
        span = max(ours) - min(ours)
        result[name] = {"max_abs_diff": diff, "range": span,
                        "fraction_of_range": diff / span if span > 0 else math.inf}
    return result


def inverse_dynamics(folder, model_path, work):
    mh, ml, mrows = read_storage(os.path.join(folder, "motion.mot"))
    gh, gl, grows = read_storage(os.path.join(folder, "grf.mot"))
    tx = ml.index("pelvis_tx")
    # the cycle's duration and forward displacement (average speed × duration)
    with open(os.path.join(folder, "summary.json")) as f:
        outcomes = json.load(f)["outcomes"]
    period = outcomes["cycle_duration"]
    stride = outcomes["speed"] * period
    motion = os.path.join(work, "motion.mot")
    write_storage(motion, mh, ml, tile(mrows, period, {tx: stride}))
    grf = os.path.join(work, "grf.mot")
    write_storage(grf, gh, gl, tile(grows, period, {gl.index(f"{s}_ground_force_px"): stride
                                                     for s in "rl"}))
    loads = osim.ExternalLoads(os.path.join(folder, "grf.xml"), True)
    loads.setDataFileName(grf)
    loads_path = os.path.join(work, "grf.xml")
    loads.printToXML(loads_path)
    model = osim.Model(model_path)
    model.initSystem()
    # every model force off (muscles, contact spheres, actuators): the tool does not
    # honour single force names here, "All" it does
    excluded = osim.ArrayStr()
    excluded.append("All")
    tool = osim.InverseDynamicsTool()
    tool.setModel(model)
    tool.setCoordinatesFileName(motion)
    tool.setExternalLoadsFileName(loads_path)
    tool.setExcludedForces(excluded)
    tool.setLowpassCutoffFrequency(-1)
    tool.setStartTime(0.0)
    tool.setEndTime(mrows[-1][0])
    tool.setResultsDir(work)
    tool.setOutputGenForceFileName("id.sto")
    if not tool.run():
        raise RuntimeError("InverseDynamicsTool failed")
    return compare_with_joint_torques(folder, os.path.join(work, "id.sto"), grows, gl)


def compare_with_joint_torques(folder, sto, grows, gl):
    """Per checked coordinate, the largest difference between the torques of the storage
    `sto` and joint_torques.csv (nearest time), as a fraction of that torque's range, also
    away from the heel strikes (rows of grf.mot `grows` with labels `gl`)."""
    table = osim.TimeSeriesTable(sto)
    times = list(table.getIndependentColumn())
    with open(os.path.join(folder, "joint_torques.csv")) as f:
        rows = list(csv.reader(f))
    names = [h.split(" [")[0] for h in rows[0]]
    ref = [[float(v) for v in r] for r in rows[1:]]
    # rows of joint_torques.csv at and next to each heel strike (a foot's vertical force
    # rising through 20 N between two rows)
    impact = set()
    n = len(ref)
    for side in "rl":
        vy = [value_at(grows, gl.index(f"{side}_ground_force_vy"), r[0]) for r in ref]
        for k in range(n):
            if vy[k] >= LOADED and vy[k - 1] < LOADED:
                impact.update({(k - 1) % n, k, (k + 1) % n})
    result = {}
    for name in [f"{c}_{s}" for c in CHECKED for s in "rl"] + LUMBAR:
        if name not in names:
            continue
        col = names.index(name)
        label = next((l for l in table.getColumnLabels()
                      if l in (f"{name}_moment", f"{name}_force")), None)
        if label is None:
            continue
        ours = [r[col] for r in ref]
        theirs = table.getDependentColumn(label).to_numpy()
        diffs = []
        for r in ref:
            i = min(range(len(times)), key=lambda k: abs(times[k] - r[0]))
            diffs.append(abs(float(theirs[i]) - r[col]))
        span = max(ours) - min(ours)
        away = [d for k, d in enumerate(diffs) if k not in impact]
        frac = lambda d: d / span if span > 0 else math.inf
        result[name] = {"max_abs_diff": max(diffs), "range": span,
                        "fraction_of_range": frac(max(diffs)),
                        "fraction_of_range_away_from_heel_strikes": frac(max(away))}
    return result


def setup_file_inverse_dynamics(folder, work):
    """Run the folder's own id_setup.xml as OpenSim runs a setup file (`opensim-cmd
    run-tool`: an InverseDynamicsTool constructed from the file), on a copy of the files
    it names so that the result folder is not written to, and compare its torques with
    joint_torques.csv."""
    for name in ["id_setup.xml", "model.osim", "motion.mot", "grf.mot", "grf.xml"]:
        shutil.copy(os.path.join(folder, name), os.path.join(work, name))
    setup = os.path.join(work, "id_setup.xml")
    if shutil.which("opensim-cmd"):
        subprocess.run(["opensim-cmd", "run-tool", setup], check=True, cwd=work,
                       stdout=subprocess.DEVNULL)
    elif not osim.InverseDynamicsTool(setup).run():
        raise RuntimeError("InverseDynamicsTool failed on id_setup.xml")
    _, gl, grows = read_storage(os.path.join(folder, "grf.mot"))
    sto = os.path.join(work, "inverse_dynamics", "inverse_dynamics.sto")
    return compare_with_joint_torques(folder, sto, grows, gl)


def main(folder):
    osim.Logger.setLevelString("error")
    checks = {}
    model_path = os.path.join(folder, "model.osim")
    model = osim.Model(model_path)
    state = model.initSystem()
    checks["model_loads"] = True
    paths = set(model.getStateVariableNames().get(i)
                for i in range(model.getNumStateVariables()))
    states = osim.TimeSeriesTable(os.path.join(folder, "states.sto"))
    missing = [l for l in states.getColumnLabels() if l not in paths]
    checks["states_are_paths"] = not missing
    checks["states_not_paths"] = missing[:5]
    checks["states_columns"] = states.getNumColumns()
    actuators = set(model.getActuators().get(i).getAbsolutePathString()
                    for i in range(model.getActuators().getSize()))
    controls = osim.TimeSeriesTable(os.path.join(folder, "controls.sto"))
    missing = [l for l in controls.getColumnLabels() if l not in actuators]
    checks["controls_are_paths"] = not missing
    checks["controls_not_paths"] = missing[:5]
    traj = osim.MocoTrajectory(os.path.join(folder, "trajectory.sto"))
    checks["moco_trajectory"] = (traj.getNumStates() == states.getNumColumns()
                                 and traj.getNumControls() == controls.getNumColumns()
                                 and traj.getNumAccelerations() == model.getNumCoordinates())
    loads = osim.ExternalLoads(os.path.join(folder, "grf.xml"), True)
    checks["external_loads"] = loads.getSize() == 2
    with tempfile.TemporaryDirectory() as work:
        cwd = os.getcwd()
        os.chdir(work)
        try:
            idr = inverse_dynamics(folder, model_path, work)
        finally:
            os.chdir(cwd)
    checks["inverse_dynamics_tool"] = idr
    checks["inverse_dynamics_tool_worst"] = float(
        max((v["fraction_of_range"] for v in idr.values()), default=math.inf))
    with tempfile.TemporaryDirectory() as work:
        cwd = os.getcwd()
        os.chdir(work)
        try:
            ids = setup_file_inverse_dynamics(folder, work)
        finally:
            os.chdir(cwd)
    checks["id_setup_file"] = ids
    for key in ["fraction_of_range", "fraction_of_range_away_from_heel_strikes"]:
        checks[f"id_setup_file_worst_{key}"] = float(
            max((v[key] for v in ids.values()), default=math.inf))
    idr = solver_inverse_dynamics(folder, model_path)
    checks["inverse_dynamics"] = idr
    cop = center_of_pressure(folder, osim.Model(model_path))
    checks["center_of_pressure"] = cop
    checks["center_of_pressure_under_foot"] = all(
        v["loaded_samples"] > 0 and v["max_distance_outside"] <= COP_TOLERANCE
        for v in cop.values())
    worst = max((v["fraction_of_range"] for v in idr.values()), default=math.inf)
    checks["inverse_dynamics_worst"] = float(worst)
    ok = all(checks[k] for k in ["model_loads", "states_are_paths", "controls_are_paths",
                                  "moco_trajectory", "external_loads",
                                  "center_of_pressure_under_foot"])
    checks["inverse_dynamics_within_tolerance"] = bool(worst <= TOLERANCE and len(idr) > 0)
    # one line, the last on stdout
    print(json.dumps(checks))
    return 0 if ok and checks["inverse_dynamics_within_tolerance"] else 1


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    sys.exit(main(os.path.abspath(sys.argv[1])))
