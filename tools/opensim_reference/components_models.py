"""Small test models for the elements Moco-built models use, with OpenSim 4.6's numbers.

Usage: components_models.py OUT_DIR
Writes OUT_DIR/two_link_components.osim: two links on pin joints (hip_flex, knee_angle)
with
- `knee_spring`, an ExpressionBasedCoordinateForce on knee_angle, in the model's
  <components> list (Model.addComponent);
- `biarticular`, a DeGrooteFregly2016Muscle on a FunctionBasedPath whose length is a
  MultivariatePolynomialFunction of (hip_flex, knee_angle), order 3;
- `monoarticular`, a DeGrooteFregly2016Muscle on a FunctionBasedPath, polynomial of
  knee_angle (order 2), in the <components> list;
and OUT_DIR/two_link_components.json: at random states in the coordinate ranges, the
expression force's value (`calcExpressionForce`), the generalised forces it applies
(inverse dynamics with only it enabled, minus inverse dynamics with no force), and each
path's length and moment arms (`computeMomentArm`) about both coordinates.
"""
import json
import os
import random
import sys

import opensim as osim

EXPRESSION = "-40*(q-0.5) - 2.5*qdot + 3*sin(q)^2 + 0.1*exp(-q/0.2)"


def polynomial(dimension, order, coefficients):
    f = osim.MultivariatePolynomialFunction()
    f.setDimension(dimension)
    f.setOrder(order)
    f.setCoefficients(osim.Vector(coefficients))
    return f


def muscle(name, coordinate_paths, function):
    m = osim.DeGrooteFregly2016Muscle()
    m.setName(name)
    m.set_max_isometric_force(1000.0)
    m.set_optimal_fiber_length(0.1)
    m.set_tendon_slack_length(0.2)
    path = osim.FunctionBasedPath()
    for c in coordinate_paths:
        path.appendCoordinatePath(c)
    path.setLengthFunction(function)
    m.set_path(path)
    return m


def build():
    model = osim.Model()
    model.setName("two_link_components")
    thigh = osim.Body("thigh", 5.0, osim.Vec3(0, -0.2, 0), osim.Inertia(0.1, 0.02, 0.1))
    shank = osim.Body("shank", 3.0, osim.Vec3(0, -0.2, 0), osim.Inertia(0.05, 0.01, 0.05))
    model.addBody(thigh)
    model.addBody(shank)
    hip = osim.PinJoint("hip", model.getGround(), osim.Vec3(0, 1, 0), osim.Vec3(0),
                        thigh, osim.Vec3(0), osim.Vec3(0))
    knee = osim.PinJoint("knee", thigh, osim.Vec3(0, -0.4, 0), osim.Vec3(0),
                         shank, osim.Vec3(0), osim.Vec3(0))
    hip.updCoordinate().setName("hip_flex")
    knee.updCoordinate().setName("knee_angle")
    hip.updCoordinate().setRangeMin(-1.0)
    hip.updCoordinate().setRangeMax(1.5)
    knee.updCoordinate().setRangeMin(0.0)
    knee.updCoordinate().setRangeMax(2.0)
    model.addJoint(hip)
    model.addJoint(knee)
    spring = osim.ExpressionBasedCoordinateForce("knee_angle", EXPRESSION)
    spring.setName("knee_spring")
    model.addComponent(spring)
    # 10 terms of order 3 in 2 variables, OpenSim's ordering.
    c2 = [0.35, -0.021, 0.004, -0.0011, 0.018, 0.0032, 0.0007, -0.006, 0.0009, 0.0012]
    model.addForce(muscle("biarticular", ["/jointset/hip/hip_flex",
                                          "/jointset/knee/knee_angle"],
                          polynomial(2, 3, c2)))
    model.addComponent(muscle("monoarticular", ["/jointset/knee/knee_angle"],
                              polynomial(1, 2, [0.28, -0.03, 0.004])))
    model.finalizeConnections()
    return model


def generalised(model, state, enabled):
    """Inverse-dynamics generalised forces with zero accelerations, only `enabled` on."""
    for f in model.getForceSet():
        f.set_appliesForce(f.getName() in enabled)
    for f in model.getComponentsList():
        if f.getName() == "knee_spring" or f.getName() == "monoarticular":
            osim.Force.safeDownCast(f).set_appliesForce(f.getName() in enabled)
    s = model.initSystem()
    s.setQ(state[0])
    s.setU(state[1])
    model.realizeVelocity(s)
    tau = osim.InverseDynamicsSolver(model).solve(s, osim.Vector(s.getNU(), 0.0))
    return [tau.get(i) for i in range(tau.size())]


def main():
    out = sys.argv[1]
    model = build()
    path = os.path.join(out, "two_link_components.osim")
    model.printToXML(path)
    model = osim.Model(path)
    s = model.initSystem()
    coords = [model.getCoordinateSet().get(n) for n in ("hip_flex", "knee_angle")]
    spring = osim.ExpressionBasedCoordinateForce.safeDownCast(
        model.getComponent("/knee_spring"))
    muscles = {"biarticular": model.getComponent("/forceset/biarticular"),
               "monoarticular": model.getComponent("/monoarticular")}
    rng = random.Random(3)
    samples = []
    for _ in range(12):
        q = [round(rng.uniform(-1.0, 1.5), 6), round(rng.uniform(0.0, 2.0), 6)]
        u = [round(rng.uniform(-3, 3), 6), round(rng.uniform(-3, 3), 6)]
        for c, qi, ui in zip(coords, q, u):
            c.setValue(s, qi, False)
            c.setSpeedValue(s, ui)
        model.realizeVelocity(s)
        row = {"q": q, "u": u, "expression_force": spring.calcExpressionForce(s)}
        for name, m in muscles.items():
            path = osim.FunctionBasedPath.safeDownCast(
                osim.Muscle.safeDownCast(m).getPath())
            row[name] = {
                "length": path.getLength(s),
                "moment_arms": [path.computeMomentArm(s, c) for c in coords],
            }
        samples.append((row, osim.Vector(s.getQ()), osim.Vector(s.getU())))
    rows = []
    for row, q, u in samples:
        none = generalised(model, (q, u), set())
        with_spring = generalised(model, (q, u), {"knee_spring"})
        # Inverse dynamics gives the forces the motors must add: an applied generalised
        # force τ lowers them by τ.
        row["spring_generalised_forces"] = [b - a for a, b in zip(with_spring, none)]
        rows.append(row)
    with open(os.path.join(out, "two_link_components.json"), "w") as f:
        json.dump({"expression": EXPRESSION, "samples": rows}, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
