"""Active force-length and passive force multipliers of OpenSim 4.6's
DeGrooteFregly2016Muscle with `active_force_width_scale` 1.4 and with
`ignore_passive_fiber_force` on.

Usage: de_groote_options.py OUT.json
"""
import json
import sys

import opensim as osim

X = [0.45, 0.7, 0.9, 1.0, 1.15, 1.3, 1.55, 1.8]


def main():
    wide = osim.DeGrooteFregly2016Muscle()
    wide.set_active_force_width_scale(1.4)
    plain = osim.DeGrooteFregly2016Muscle()
    out = {
        "active_force_width_scale": 1.4,
        "normalized_fiber_length": X,
        "active_force_length_wide": [wide.calcActiveForceLengthMultiplier(x) for x in X],
        "active_force_length": [plain.calcActiveForceLengthMultiplier(x) for x in X],
        "passive_force": [plain.calcPassiveForceMultiplier(x) for x in X],
    }
    with open(sys.argv[1], "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
