#!/usr/bin/env python3
"""OpenSim reference numbers for the skeleton and the non-muscle forces of a model.

For one `.osim` file this writes a compact JSON with
  * every body's mass [kg], centre of mass [m] and inertia about it [kg m^2] (body axes);
  * inverse dynamics at random states (q, qdot, qddot in the coordinate ranges) with every
    force element disabled, so only the skeleton and gravity are compared;
  * inverse dynamics with only the SmoothSphereHalfSpaceForce contacts enabled, at states
    near the ground (the lowest sphere penetrating 0-10 mm), with each sphere's force and
    torque on its body (ground frame, torque about the body origin);
  * length [m] and tension [N] of every Ligament at random states;
  * generalised force of every CoordinateLimitForce and SpringGeneralizedForce at random
    states.
OpenSim 4.6 rounds the centres of mass, inertias and joint offsets of an OpenSim 3.x file
to 6 significant digits when it converts the file on loading; the script restores them
from the file text, so the reference uses the numbers the file holds.
Coordinates are unlocked and unclamped (inverse dynamics ignores constraints); values are
set straight into the state (no assembly).

Usage: dynamics_reference.py MODEL.osim OUT.json [--states 50] [--seed 1]
"""

import argparse
import json
import math
import os
import xml.etree.ElementTree as ET

import numpy as np
import opensim as osim

FORCE_LAWS = ("CoordinateLimitForce", "SpringGeneralizedForce")


def load(path, enabled):
    """Model with only the force classes in `enabled` applying force, coordinates free."""
    model = osim.Model(path)
    restore_v3_precision(model, path)
    forces = model.updForceSet()
    for i in range(forces.getSize()):
        f = forces.get(i)
        f.set_appliesForce(f.getConcreteClassName() in enabled)
    coords = model.updCoordinateSet()
    for i in range(coords.getSize()):
        coords.get(i).set_locked(False)
        coords.get(i).set_clamped(False)
    state = model.initSystem()
    return model, state


def vec3(el, tag):
    t = el.find(tag)
    return osim.Vec3(*[float(x) for x in t.text.split()]) if t is not None else None


def restore_v3_precision(model, path):
    """Full-precision body and joint-frame numbers of an OpenSim 3.x file."""
    root = ET.parse(path).getroot()
    if int(root.get("Version")) >= 40000:
        return
    for b in root.iter("Body"):
        if b.get("name") == "ground" or not model.getBodySet().contains(b.get("name")):
            continue
        body = model.updBodySet().get(b.get("name"))
        body.setMassCenter(vec3(b, "mass_center"))
        i = [float(b.find("inertia_" + k).text) for k in ("xx", "yy", "zz", "xy", "xz", "yz")]
        body.setInertia(osim.Inertia(*i))
        joint_el = b.find("Joint")
        j = next(iter(joint_el), None) if joint_el is not None else None
        if j is None:
            continue
        joint = model.updJointSet().get(j.get("name"))
        parent = joint.getSocket("parent_frame").getConnecteePath()
        for k in range(joint.getPropertyByName("frames").size()):
            f = joint.upd_frames(k)
            loc, ori = (("location_in_parent", "orientation_in_parent")
                        if f.getName() == parent else ("location", "orientation"))
            if vec3(j, loc) is not None:
                f.set_translation(vec3(j, loc))
            if vec3(j, ori) is not None:
                f.set_orientation(vec3(j, ori))


def coordinate_indices(model, state):
    """For each coordinate (model order): its q and u index in the state."""
    coords = model.getCoordinateSet()
    out = []
    for i in range(coords.getSize()):
        c = coords.get(i)
        state.setQ(osim.Vector(state.getNQ(), 0.0))
        state.setU(osim.Vector(state.getNU(), 0.0))
        c.setValue(state, 0.5, False)
        c.setSpeedValue(state, 0.5)
        q = [k for k in range(state.getNQ()) if state.getQ().get(k) != 0.0]
        u = [k for k in range(state.getNU()) if state.getU().get(k) != 0.0]
        if len(q) != 1 or len(u) != 1:
            raise SystemExit(f"coordinate {c.getName()} maps to q {q}, u {u}")
        out.append((c.getName(), q[0], u[0]))
    return out


def sample_state(model, rng, index, near=None, vel=2.0, acc=10.0):
    """Random q in the coordinate ranges (or default +/- 0.2 when `near`), qdot, qddot."""
    coords = model.getCoordinateSet()
    q, qd, qdd = [], [], []
    for i in range(coords.getSize()):
        c = coords.get(i)
        lo, hi = c.getRangeMin(), c.getRangeMax()
        if not (math.isfinite(lo) and math.isfinite(hi)) or hi - lo > 20:
            lo, hi = -1.0, 1.0
        if near is not None:
            d = c.getDefaultValue()
            w = 0.2 if c.getMotionType() == 1 else 0.02
            lo, hi = max(lo, d - w), min(hi, d + w)
            if hi < lo:
                lo = hi = d
        # Inputs rounded to 6 decimals: the file then holds them exactly.
        q.append(round(rng.uniform(lo, hi), 6))
        qd.append(round(rng.uniform(-vel, vel), 6))
        qdd.append(round(rng.uniform(-acc, acc), 6))
    return q, qd, qdd


def set_state(model, state, index, q, qd):
    qv = osim.Vector(state.getNQ(), 0.0)
    uv = osim.Vector(state.getNU(), 0.0)
    for (name, qi, ui), a, b in zip(index, q, qd):
        qv.set(qi, a)
        uv.set(ui, b)
    state.setQ(qv)
    state.setU(uv)
    model.realizeVelocity(state)


def inverse_dynamics(model, state, index, q, qd, qdd):
    set_state(model, state, index, q, qd)
    udot = osim.Vector(state.getNU(), 0.0)
    for (name, qi, ui), a in zip(index, qdd):
        udot.set(ui, a)
    tau = osim.InverseDynamicsSolver(model).solve(state, udot)
    return [tau.get(ui) for (_, _, ui) in index]


def bodies(model):
    out = []
    bs = model.getBodySet()
    for i in range(bs.getSize()):
        b = bs.get(i)
        inertia = b.getInertia()
        mo, pr = inertia.getMoments(), inertia.getProducts()
        out.append({
            "name": b.getName(),
            "mass": b.getMass(),
            "com": [b.getMassCenter().get(k) for k in range(3)],
            "inertia": [mo.get(0), mo.get(1), mo.get(2), pr.get(0), pr.get(1), pr.get(2)],
        })
    return out


def forces_of(model, cls):
    fs = model.getForceSet()
    return [fs.get(i) for i in range(fs.getSize()) if fs.get(i).getConcreteClassName() == cls]


def skeleton_id(path, rng, n):
    model, state = load(path, ())
    index = coordinate_indices(model, state)
    rows = []
    for _ in range(n):
        q, qd, qdd = sample_state(model, rng, index)
        rows.append({"q": q, "qdot": qd, "qddot": qdd,
                     "tau": inverse_dynamics(model, state, index, q, qd, qdd)})
    return [name for name, _, _ in index], rows


def lowest_sphere_gap(model, state):
    """Smallest (height above its half-space plane - radius) over the contact spheres."""
    gaps = []
    for f in forces_of(model, "SmoothSphereHalfSpaceForce"):
        sph = osim.ContactSphere.safeDownCast(f.getConnectee("sphere"))
        hs = osim.ContactHalfSpace.safeDownCast(f.getConnectee("half_space"))
        c = sph.getFrame().findStationLocationInGround(state, sph.get_location())
        tf = hs.getFrame().getTransformInGround(state)
        geo = hs.getTransform()
        loc = tf.shiftFrameStationToBase(geo.p())
        nx = tf.R().multiply(geo.R().multiply(osim.Vec3(-1, 0, 0)))
        h = sum((c.get(k) - loc.get(k)) * nx.get(k) for k in range(3))
        gaps.append(h - sph.getRadius())
    return min(gaps)


def contact_id(path, rng, n):
    model, state = load(path, ("SmoothSphereHalfSpaceForce",))
    index = coordinate_indices(model, state)
    names = [name for name, _, _ in index]
    ty = names.index("pelvis_ty")
    spheres = forces_of(model, "SmoothSphereHalfSpaceForce")
    rows = []
    for _ in range(n):
        q, qd, qdd = sample_state(model, rng, index, near=True, vel=0.5, acc=5.0)
        set_state(model, state, index, q, [0.0] * len(q))
        q[ty] = round(q[ty] - lowest_sphere_gap(model, state) - rng.uniform(0.0, 0.01), 6)
        tau = inverse_dynamics(model, state, index, q, qd, qdd)
        model.realizeDynamics(state)
        per = []
        for f in spheres:
            v = f.getRecordValues(state)
            per.append([v.get(k) for k in range(6)])
        rows.append({"q": q, "qdot": qd, "qddot": qdd, "tau": tau, "spheres": per})
    return [f.getName() for f in spheres], rows


def ligaments(path, rng, n):
    model, state = load(path, ("Ligament",))
    index = coordinate_indices(model, state)
    ligs = [osim.Ligament.safeDownCast(f) for f in forces_of(model, "Ligament")]
    rows = []
    for _ in range(n):
        q, qd, _ = sample_state(model, rng, index)
        set_state(model, state, index, q, qd)
        model.realizeDynamics(state)
        rows.append({"q": q,
                     "length": [l.getLength(state) for l in ligs],
                     "tension": [l.getTension(state) for l in ligs]})
    return [l.getName() for l in ligs], rows


def force_laws(path, rng, n):
    model, state = load(path, FORCE_LAWS)
    index = coordinate_indices(model, state)
    els = [f for cls in FORCE_LAWS for f in forces_of(model, cls)]
    rows = []
    for _ in range(n):
        q, qd, _ = sample_state(model, rng, index)
        set_state(model, state, index, q, qd)
        model.realizeDynamics(state)
        rows.append({"q": q, "qdot": qd,
                     "force": [f.getRecordValues(state).get(0) for f in els]})
    return [f.getName() for f in els], rows


def compact(v):
    """Computed results to 12 significant digits (inputs are already rounded; body
    properties are written in full)."""
    if isinstance(v, float):
        return float(f"{v:.12g}")
    if isinstance(v, list):
        return [compact(x) for x in v]
    if isinstance(v, dict):
        return {k: compact(x) for k, x in v.items()}
    return v


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model")
    ap.add_argument("out")
    ap.add_argument("--states", type=int, default=50)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    osim.Logger.setLevelString("error")
    rng = np.random.default_rng(a.seed)
    probe, _ = load(a.model, ())
    classes = {probe.getForceSet().get(i).getConcreteClassName()
               for i in range(probe.getForceSet().getSize())}
    coords, id_rows = skeleton_id(a.model, rng, a.states)
    out = {
        "model": os.path.basename(a.model),
        "opensim_version": osim.__version__,
        "seed": a.seed,
        "gravity": [probe.getGravity().get(k) for k in range(3)],
        "bodies": bodies(probe),
        "coordinates": coords,
        "inverse_dynamics": compact(id_rows),
    }
    if "SmoothSphereHalfSpaceForce" in classes:
        names, rows = contact_id(a.model, rng, a.states)
        out["contact"] = {"forces": names, "states": compact(rows)}
    if "Ligament" in classes:
        names, rows = ligaments(a.model, rng, a.states)
        out["ligaments"] = {"names": names, "states": compact(rows)}
    if classes & set(FORCE_LAWS):
        names, rows = force_laws(a.model, rng, a.states)
        out["force_laws"] = {"names": names, "states": compact(rows)}
    with open(a.out, "w") as fh:
        json.dump(out, fh, separators=(",", ":"))


if __name__ == "__main__":
    main()
