"""Write the built-in model as an OpenSim 4 model file: crates/model/data/default_model.osim.

The file is subject1_v2.osim (3dpredictsim, MIT; see README.md for the model's credits)
with what the built-in model (crates/model/data/default_model.json) adds to it and OpenSim
can express:
  * gravity of the simulations (0, -9.81, 0) m/s^2,
  * the ground half-space and the 12 contact spheres as SmoothSphereHalfSpaceForce
    elements (same names, bodies, locations, radii and contact-law parameters),
  * the 8 arm torque actuators as CoordinateActuator elements.
The passive joint torques and the polynomial muscle geometry have no OpenSim 4 element of
the same form and are not written.

Usage (from the repository root):
    /work/venv-opensim/bin/python tools/opensim_reference/default_model_osim.py \
        ../shared/reference/models/subject1_v2.osim
"""

import json
import math
import sys
from pathlib import Path

import opensim as osim

ROOT = Path(__file__).resolve().parents[2]
JSON = ROOT / "crates/model/data/default_model.json"
OUT = ROOT / "crates/model/data/default_model.osim"


def main(source):
    stride = json.loads(JSON.read_text())
    model = osim.Model(str(source))
    model.setName("subject1_v2_stride")
    model.set_gravity(osim.Vec3(*stride["gravity"]))
    bodies = [b["name"] for b in stride["bodies"]]
    contacts = stride["contacts"]
    normals = {tuple(c["plane_normal"]) for c in contacts}
    points = {tuple(c["plane_point"]) for c in contacts}
    if normals != {(0.0, 1.0, 0.0)} or points != {(0.0, 0.0, 0.0)}:
        sys.exit("the built-in model's contact plane is not y = 0 with normal +y")
    floor = osim.ContactHalfSpace(
        osim.Vec3(0, 0, 0), osim.Vec3(0, 0, -math.pi / 2), model.getGround(), "floor"
    )
    model.addContactGeometry(floor)
    for c in contacts:
        body = model.getBodySet().get(bodies[c["body"]])
        sphere = osim.ContactSphere(
            c["radius"], osim.Vec3(*c["location"]), body, c["name"] + "_geometry"
        )
        model.addContactGeometry(sphere)
        p = c["parameters"]
        force = osim.SmoothSphereHalfSpaceForce(c["name"], sphere, floor)
        force.set_stiffness(p["stiffness"])
        force.set_dissipation(p["dissipation"])
        force.set_static_friction(p["static_friction"])
        force.set_dynamic_friction(p["dynamic_friction"])
        force.set_viscous_friction(p["viscous_friction"])
        force.set_transition_velocity(p["transition_velocity"])
        force.set_constant_contact_force(p["constant_contact_force"])
        force.set_hertz_smoothing(p["hertz_smoothing"])
        force.set_hunt_crossley_smoothing(p["hunt_crossley_smoothing"])
        model.addForce(force)
    coords = [c["name"] for c in stride["coordinates"]]
    for a in stride["actuators"]:
        act = osim.CoordinateActuator(coords[a["coordinate"]])
        act.setName(a["name"])
        act.setOptimalForce(a["optimal_force"])
        act.setMinControl(a["control_range"][0])
        act.setMaxControl(a["control_range"][1])
        model.addForce(act)
    model.finalizeConnections()
    model.initSystem()
    model.printToXML(str(OUT))
    print(f"wrote {OUT}")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(Path(sys.argv[1]))
