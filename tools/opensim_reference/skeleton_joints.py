#!/usr/bin/env python3
"""A small OpenSim 4 model with every joint kind, function type, a coordinate coupler, a
CoordinateLimitForce and a SpringGeneralizedForce, and its OpenSim reference numbers.

Writes MODEL.osim (the model, built here with the OpenSim API) and OUT.json with
  * bodies (mass, centre of mass, inertia);
  * inverse dynamics with gravity only at random states, in stride's convention: the
    speeds of the BallJoint and FreeJoint rotations are the angle rates (OpenSim's are
    the angular velocity), converted as in `inverse_dynamics`; the coupled coordinate's
    value, speed and acceleration follow the coupler function and its force is moved
    onto the independent coordinate (τ_i += f'(q_i) τ_d, τ_d = 0), as stride eliminates it;
  * the generalised force of the CoordinateLimitForce and the SpringGeneralizedForce at
    random states (limit force states spread around the limits).

Usage: skeleton_joints.py MODEL.osim OUT.json [--states 60] [--seed 2]
"""

import argparse
import json
import os
import sys

import numpy as np
import opensim as osim

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dynamics_reference import (  # noqa: E402
    bodies, compact, coordinate_indices, forces_of, set_state)

V = osim.Vec3

# The custom joint's axes: coordinate, axis, function as the file holds it. Functions are
# written into the file text after the model is printed (the Python bindings alias
# function objects handed to several owners, and do not wrap NaturalCubicSpline, which
# OpenSim 4 reads as a SimmSpline).
CUSTOM_AXES = [
    ("rotation1", "c1", "0.3 0.2 1", '<NaturalCubicSpline name="function"><x>-2 -0.5 0.4 1.5 '
     '2.5</x><y>-1.8 -0.6 0.5 1.2 2.6</y></NaturalCubicSpline>'),
    ("rotation2", "c2", "1 0 0", '<PiecewiseLinearFunction name="function"><x>-2 -0.3 0.6 '
     '2.2</x><y>-1 -0.2 0.7 1.1</y></PiecewiseLinearFunction>'),
    ("rotation3", "c3", "0 1 0", '<PolynomialFunction name="function"><coefficients>0.1 -0.2 '
     '1.1 0.05</coefficients></PolynomialFunction>'),
    ("translation1", "c2", "1 0 0", '<MultiplierFunction name="function"><function>'
     '<SimmSpline><x>-2 -1 0 1 2.5</x><y>-0.05 -0.02 0 0.03 0.04</y></SimmSpline>'
     '</function><scale>1.5</scale></MultiplierFunction>'),
    ("translation2", "c3", "0 1 0", '<LinearFunction name="function"><coefficients>0.02 '
     '0.01</coefficients></LinearFunction>'),
    ("translation3", None, "0 0 1", '<Constant name="function"><value>0.015</value></Constant>'),
]


def body(model, name, mass, com, inertia):
    b = osim.Body(name, mass, V(*com), osim.Inertia(*inertia))
    model.addBody(b)
    return b


def custom_transform():
    """The custom joint's axes with their coordinates (functions follow in the text)."""
    st = osim.SpatialTransform()
    for k, (_, coord, axis, _) in enumerate(CUSTOM_AXES):
        ax = st.updTransformAxis(k)
        names = osim.ArrayStr()
        if coord:
            names.append(coord)
        ax.setCoordinateNames(names)
        ax.setAxis(V(*[float(x) for x in axis.split()]))
    return st


def write_custom_functions(path):
    """Give each custom axis the function of CUSTOM_AXES (printed without one)."""
    text = open(path).read()
    for name, _, _, xml in CUSTOM_AXES:
        start = text.index(f'<TransformAxis name="{name}">')
        end = text.index("</TransformAxis>", start)
        assert 'name="function"' not in text[start:end], name
        text = text[:end] + xml + text[end:]
    with open(path, "w") as fh:
        fh.write(text)


def build(path):
    m = osim.Model()
    m.setName("joint_kinds")
    m.setGravity(V(0.3, -9.80665, -0.2))
    inertia = lambda s: (0.05 * s, 0.04 * s, 0.03 * s, 0.004 * s, -0.003 * s, 0.002 * s)
    names = ["free", "ball", "gimbal", "universal", "planar", "slider", "pin", "custom", "weld"]
    bs = [body(m, f"b_{n}", 1.0 + 0.3 * k, (0.02 * k, -0.1, 0.03), inertia(1 + 0.2 * k))
          for k, n in enumerate(names)]
    ori = lambda k: V(0.1 * k, -0.2 + 0.05 * k, 0.3 - 0.04 * k)
    loc = lambda k: V(0.01 * k, -0.2, 0.02)
    parent = m.getGround()
    for k, n in enumerate(names):
        args = (f"j_{n}", parent, loc(k), ori(k), bs[k], V(0.01, 0.05, -0.02), ori(k + 1))
        if n == "free":
            j = osim.FreeJoint(*args)
        elif n == "ball":
            j = osim.BallJoint(*args)
        elif n == "universal":
            j = osim.UniversalJoint(*args)
        elif n == "planar":
            j = osim.PlanarJoint(*args)
        elif n == "gimbal":
            j = osim.GimbalJoint(*args)
        elif n == "slider":
            j = osim.SliderJoint(*args)
        elif n == "pin":
            j = osim.PinJoint(*args)
        elif n == "custom":
            st = custom_transform()
            j = osim.CustomJoint(*args, st)
        else:
            j = osim.WeldJoint(*args)
        for c in range(j.numCoordinates()):
            coord = j.upd_coordinates(c)
            if n != "custom":
                coord.setName(f"{n}_{c}")
            coord.setRangeMin(-1.5)
            coord.setRangeMax(1.5)
        m.addJoint(j)
        parent = bs[k]
    cc = osim.CoordinateCouplerConstraint()
    cc.setName("couple_c3")
    ind = osim.ArrayStr()
    ind.append("c1")
    cc.setIndependentCoordinateNames(ind)
    cc.setDependentCoordinateName("c3")
    cc.setFunction(osim.PolynomialFunction(osim.Vector([0.3, -0.1, 0.8, 0.05])))
    m.addConstraint(cc)
    lim = osim.CoordinateLimitForce("pin_0", 40.0, 2.0, -30.0, 3.0, 0.05, 5.0)
    lim.setName("pin_limit")
    m.addForce(lim)
    spring = osim.SpringGeneralizedForce("slider_0")
    spring.setName("slider_spring")
    spring.setStiffness(120.0)
    spring.setRestLength(0.1)
    spring.setViscosity(3.0)
    m.addForce(spring)
    m.finalizeConnections()
    m.printToXML(path)
    write_custom_functions(path)


def coupler_values(model, q, qd, qdd, names):
    """Fill the dependent coordinate from the coupler; returns its index, f'."""
    cc = osim.CoordinateCouplerConstraint.safeDownCast(model.getConstraintSet().get(0))
    f = cc.getFunction()
    i, d = names.index("c1"), names.index("c3")
    x = osim.Vector(1, q[i])
    d1 = f.calcDerivative(osim.StdVectorInt([0]), x)
    d2 = f.calcDerivative(osim.StdVectorInt([0, 0]), x)
    q[d] = f.calcValue(x)
    qd[d] = d1 * qd[i]
    qdd[d] = d1 * qdd[i] + d2 * qd[i] ** 2
    return i, d, d1


def euler_rates(q, qd):
    """E with ω_F = E q̇ for body-fixed x-y-z angles q (ω of M in F, F components), and
    Ė q̇."""
    def rot(axis, a):
        c, s_ = np.cos(a), np.sin(a)
        i, j = [(1, 2), (2, 0), (0, 1)][axis]
        r = np.eye(3)
        r[i, i], r[i, j], r[j, i], r[j, j] = c, -s_, s_, c
        return r
    ex, ey, ez = np.eye(3)
    a2 = rot(0, q[0]) @ ey
    a3 = rot(0, q[0]) @ rot(1, q[1]) @ ez
    e = np.column_stack([ex, a2, a3])
    a2dot = np.cross(ex * qd[0], a2)
    a3dot = np.cross(ex * qd[0] + a2 * qd[1], a3)
    return e, a2dot * qd[1] + a3dot * qd[2]


def inverse_dynamics(model, state, index, names, q, qd, qdd):
    """τ conjugate to q̇ for q, q̇, q̈ in coordinate order. OpenSim's speeds of the Ball
    and Free rotations are the angular velocity ω_F = E q̇ (checked: their
    coordinates are body-fixed x-y-z angles), so u = E q̇, u̇ = E q̈ + Ė q̇, τ = Eᵀ τ_u."""
    u, udot = np.array(qd, float), np.array(qdd, float)
    maps = []
    for prefix in ("free", "ball"):
        k = [names.index(f"{prefix}_{i}") for i in range(3)]
        e, edot_qd = euler_rates(np.array(q)[k], np.array(qd)[k])
        u[k] = e @ np.array(qd)[k]
        udot[k] = e @ np.array(qdd)[k] + edot_qd
        maps.append((k, e))
    set_state(model, state, index, q, list(u))
    ud = osim.Vector(state.getNU(), 0.0)
    for (_, _, ui), a in zip(index, udot):
        ud.set(ui, float(a))
    tau_u = osim.InverseDynamicsSolver(model).solve(state, ud)
    tau = np.array([tau_u.get(ui) for (_, _, ui) in index])
    for k, e in maps:
        tau[k] = e.T @ tau[k]
    return [float(t) for t in tau]


def load(path, enabled):
    model = osim.Model(path)
    for f in [model.updForceSet().get(i) for i in range(model.getForceSet().getSize())]:
        f.set_appliesForce(f.getConcreteClassName() in enabled)
    state = model.initSystem()
    return model, state


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model")
    ap.add_argument("out")
    ap.add_argument("--states", type=int, default=60)
    ap.add_argument("--seed", type=int, default=2)
    a = ap.parse_args()
    osim.Logger.setLevelString("error")
    rng = np.random.default_rng(a.seed)
    build(a.model)
    model, state = load(a.model, ())
    index = coordinate_indices(model, state)
    names = [n for n, _, _ in index]
    rows = []
    for _ in range(a.states):
        q = [round(x, 6) for x in rng.uniform(-1.2, 1.2, len(names))]
        qd = [round(x, 6) for x in rng.uniform(-2, 2, len(names))]
        qdd = [round(x, 6) for x in rng.uniform(-10, 10, len(names))]
        inputs = (list(q), list(qd), list(qdd))
        i, d, d1 = coupler_values(model, q, qd, qdd, names)
        tau = inverse_dynamics(model, state, index, names, q, qd, qdd)
        tau[i] += d1 * tau[d]
        tau[d] = 0.0
        rows.append({"q": inputs[0], "qdot": inputs[1], "qddot": inputs[2], "tau": tau})
    model, state = load(a.model, ("CoordinateLimitForce", "SpringGeneralizedForce"))
    index = coordinate_indices(model, state)
    els = forces_of(model, "CoordinateLimitForce") + forces_of(model, "SpringGeneralizedForce")
    force_rows = []
    for _ in range(a.states):
        q = [round(x, 6) for x in rng.uniform(-1.0, 1.0, len(names))]
        qd = [round(x, 6) for x in rng.uniform(-2, 2, len(names))]
        # Spread the pin angle over both limits and their transitions (-30, 40 deg).
        q[names.index("pin_0")] = round(rng.uniform(-0.65, 0.8), 6)
        set_state(model, state, index, q, qd)
        model.realizeDynamics(state)
        force_rows.append({"q": q, "qdot": qd,
                           "force": [f.getRecordValues(state).get(0) for f in els]})
    out = {
        "model": os.path.basename(a.model),
        "opensim_version": osim.__version__,
        "seed": a.seed,
        "gravity": [model.getGravity().get(k) for k in range(3)],
        "bodies": bodies(model),
        "coordinates": names,
        "inverse_dynamics": compact(rows),
        "force_laws": {"names": [f.getName() for f in els], "states": compact(force_rows)},
    }
    with open(a.out, "w") as fh:
        json.dump(out, fh, separators=(",", ":"))
    # Skip the interpreter's teardown: the bindings double-free the built model there.
    sys.stdout.flush()
    os._exit(0)


if __name__ == "__main__":
    main()
