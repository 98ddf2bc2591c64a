"""Check a stride result folder with OpenSim 4 (and Moco): the files open as they are, and
OpenSim's own inverse dynamics reproduces the folder's joint torques.

Usage:  python check_result_folder.py <result folder>   (OpenSim 4.6 Python bindings)

Prints one JSON object on stdout and exits with status 1 when a check fails:
  model_loads          model.osim loads and initialises;
  states_are_paths     every column of states.sto (read as a TimeSeriesTable) is a state
                       variable path of that model;
  controls_are_paths   every column of controls.sto is an actuator path of that model;
  moco_trajectory      trajectory.sto reads as a MocoTrajectory with the states and controls;
  external_loads       grf.xml (with grf.mot) loads as ExternalLoads with two forces;
  inverse_dynamics     per coordinate, the largest difference over the cycle between
                       OpenSim's InverseDynamicsTool (model.osim, motion.mot, grf.xml; model
                       forces excluded, so only gravity, inertia and the ground reactions act)
                       and joint_torques.csv, as a fraction of that torque's range over the
                       cycle. The cycle is periodic: the motion and the ground reactions are
                       extended by one cycle before and after it (forward position shifted
                       by the stride) so that the tool's splines have no end effects, and the
                       tool's torques are compared on the middle cycle.
"""

import csv
import json
import math
import os
import sys
import tempfile

import opensim as osim

CHECKED = ["hip_flexion", "hip_adduction", "hip_rotation", "knee_angle", "ankle_angle",
           "subtalar_angle"]
LUMBAR = ["lumbar_extension", "lumbar_bending", "lumbar_rotation"]
TOLERANCE = 0.05


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


def inverse_dynamics(folder, model_path, work):
    mh, ml, mrows = read_storage(os.path.join(folder, "motion.mot"))
    gh, gl, grows = read_storage(os.path.join(folder, "grf.mot"))
    dt = mrows[1][0] - mrows[0][0]
    period = mrows[-1][0] + dt
    tx = ml.index("pelvis_tx")
    # the cycle's forward displacement (average speed × cycle duration, summary.json)
    with open(os.path.join(folder, "summary.json")) as f:
        outcomes = json.load(f)["outcomes"]
    stride = outcomes["speed"] * outcomes["cycle_duration"]
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
    table = osim.TimeSeriesTable(os.path.join(work, "id.sto"))
    times = list(table.getIndependentColumn())
    with open(os.path.join(folder, "joint_torques.csv")) as f:
        rows = list(csv.reader(f))
    names = [h.split(" [")[0] for h in rows[0]]
    ref = [[float(v) for v in r] for r in rows[1:]]
    # samples at and next to each heel strike (a foot's vertical force rising through
    # 20 N): the impact is faster than a spline through the samples can follow
    impact = set()
    n = len(grows)
    for side in "rl":
        vy = [r[gl.index(f"{side}_ground_force_vy")] for r in grows]
        for k in range(n):
            if vy[k] >= 20.0 and vy[k - 1] < 20.0:
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
                                 and traj.getNumControls() == controls.getNumColumns())
    loads = osim.ExternalLoads(os.path.join(folder, "grf.xml"), True)
    checks["external_loads"] = loads.getSize() == 2
    with tempfile.TemporaryDirectory() as work:
        cwd = os.getcwd()
        os.chdir(work)
        try:
            idr = inverse_dynamics(folder, model_path, work)
        finally:
            os.chdir(cwd)
    checks["inverse_dynamics"] = idr
    worst = max((v["fraction_of_range"] for v in idr.values()), default=math.inf)
    checks["inverse_dynamics_worst"] = float(worst)
    ok = all(checks[k] for k in ["model_loads", "states_are_paths", "controls_are_paths",
                                  "moco_trajectory", "external_loads"])
    checks["inverse_dynamics_within_tolerance"] = bool(worst <= TOLERANCE and len(idr) > 0)
    # one line, the last on stdout
    print(json.dumps(checks))
    return 0 if ok and checks["inverse_dynamics_within_tolerance"] else 1


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    sys.exit(main(os.path.abspath(sys.argv[1])))
