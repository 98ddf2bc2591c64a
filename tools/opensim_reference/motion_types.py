"""Motion type (OpenSim `Coordinate.getMotionType()`) of every coordinate of some models.

Usage: motion_types.py OUT.json MODEL.osim [MODEL.osim ...]
Writes {"<file name>": {"<coordinate>": "Rotational" | "Translational" | "Coupled"}}.
"""
import json
import os
import sys

import opensim as osim

NAMES = {
    osim.Coordinate.Rotational: "Rotational",
    osim.Coordinate.Translational: "Translational",
    osim.Coordinate.Coupled: "Coupled",
}


def motion_types(path):
    model = osim.Model(path)
    model.initSystem()
    out = {}
    for c in model.getCoordinateSet():
        out[c.getName()] = NAMES[c.getMotionType()]
    return out


def main():
    out_path = sys.argv[1]
    result = {os.path.basename(p): motion_types(p) for p in sys.argv[2:]}
    with open(out_path, "w") as f:
        json.dump(result, f, indent=1, sort_keys=True)
        f.write("\n")


if __name__ == "__main__":
    main()
