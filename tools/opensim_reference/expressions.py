"""Values of ExpressionBasedCoordinateForce expressions as OpenSim 4.6 evaluates them.

Usage: expressions.py OUT.json
For each expression: a one-coordinate model (pin joint) with the force; the force value
(`calcExpressionForce`) at a few (q, qdot) states, or `rejected` when OpenSim refuses the
expression (parse error at initSystem or unknown variable at evaluation).
"""
import json
import sys

import opensim as osim

ACCEPTED = [
    "q", "-q^2", "2^3^2", "q*-2", "1e-1*q", ".5*q", "-2^2", "3-2-1", "8/2/2", "q^-1",
    "2e+1*qdot", "q^0.5", "-q^0.5", "a*q; a=2", "a*b; a=qdot+b; b=q^2",
    "sqrt(q)", "exp(q)", "log(q)", "sin(q)", "cos(q)", "sec(q)", "csc(q)", "tan(q)",
    "cot(q)", "asin(q)", "acos(q)", "atan(q)", "sinh(q)", "cosh(q)", "tanh(q)", "erf(q)",
    "erfc(q)", "erf(5*q)", "erfc(6*q)", "step(q-0.3)", "step(0)", "delta(0)", "delta(q)",
    "square(q)", "cube(q)", "recip(q)", "min(q,qdot)", "max(q, qdot)", "abs(-q)",
    "-10 * (q - 0.2) - 0.5 * qdot", "qdot^q", "(q+qdot)^(1/3)",
    "- 20*exp(-(q-0.1)/0.05) + 3 * max(0, q - 0.6)^2",
]
REJECTED = [
    "pi", "E", "x", "Q", "q q", "floor(q)", "ceil(q)", "select(q,1,2)", "atan2(q,qdot)",
    "foo(q)", "q+", "(q", "q)", "2(q)", "sqrt(q,q)", "", "q*+2", "+q", "1.5.2", "min(q)",
    "sqrt()", "q;=2", "q;a", "q,q",
]
STATES = [(0.4, 0.7), (0.15, -1.3), (0.9, 2.2)]


def model_with(expression):
    m = osim.Model()
    b = osim.Body("b", 1.0, osim.Vec3(0), osim.Inertia(1))
    m.addBody(b)
    j = osim.PinJoint("j", m.getGround(), b)
    j.updCoordinate().setName("q")
    m.addJoint(j)
    f = osim.ExpressionBasedCoordinateForce("q", expression)
    f.setName("f")
    m.addForce(f)
    return m, f


def values(expression):
    m, f = model_with(expression)
    s = m.initSystem()
    out = []
    for q, qd in STATES:
        m.setStateVariableValue(s, "/jointset/j/q/value", q)
        m.setStateVariableValue(s, "/jointset/j/q/speed", qd)
        m.realizeVelocity(s)
        v = f.calcExpressionForce(s)
        out.append([q, qd, v if v == v else None])  # NaN is written as null
    return out


def rejected(expression):
    try:
        values(expression)
    except Exception:  # noqa: BLE001 (any OpenSim error means rejected)
        return True
    return False


def main():
    accepted = [{"expression": e, "samples": values(e)} for e in ACCEPTED]
    for e in REJECTED:
        assert rejected(e), f"OpenSim accepts {e!r}"
    with open(sys.argv[1], "w") as f:
        json.dump({"accepted": accepted, "rejected": REJECTED}, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
