"""Write the settings files of the PredSim models shipped in crates/model/data/models/.

PredSim's rules (../shared/reference/PREDSIM.md sections 3.4, 3.6, 4, 5, 8), written out
per model: limit torques of the FORMULATION 6.1 table by coordinate name (plus the mtp
row), damping 0.1 N m s/rad on every coordinate that is not the floating base, the mtp
spring and damping of each model, the problem defaults PredSim's settings of each model
set (toes driven passively, the mesh), the tendon stiffness scale 0.5 of the calf muscles
(gait1018: names containing soleus or gastroc; DHondt: soleus or _gas), DHondt's passive fibre
shift 0.9 (soleus, _gas, per_, tib_, _dig_, _hal_, FDB) and metabolic b = 100, metabolic parameters by exact muscle name (gait2392
values; the 2D model's lumped muscles; 0.5 / 0.25 MPa otherwise) and the distance
constraints. Usage (from the repository root):

    python3 tools/models/predsim_settings.py ../shared/reference
"""

import json
import re
import sys
from pathlib import Path

REF = Path(sys.argv[1] if len(sys.argv) > 1 else "../shared/reference")
OUT = Path("crates/model/data/models")

MTP_LIMIT = {"k": [-0.9, 14.87, 0.18, -70.08], "theta": [0.0, 1.13446401379631]}
DISTANCES_3D = [
    ("calcn_r", "calcn_l", 0.09),
    ("hand_r", "femur_r", 0.18),
    ("hand_l", "femur_l", 0.18),
    ("tibia_r", "tibia_l", 0.11),
    ("toes_r", "toes_l", 0.10),
]
LUMPED_2D = {  # PREDSIM.md 3.4: slow-twitch fraction, specific tension [MPa]
    "hamstrings_r": (0.5425, 0.6236),
    "glut_max_r": (0.55, 0.7477),
    "iliopsoas_r": (0.50, 1.3782),
    "vasti_r": (0.543, 0.5159),
    "gastroc_r": (0.566, 0.6981),
}
FLOATING = {"pelvis_tilt", "pelvis_list", "pelvis_rotation", "pelvis_tx", "pelvis_ty", "pelvis_tz"}


def names(osim, tag):
    return re.findall(r'<%s name="([^"]*)"' % tag, osim)


def num(x):
    return repr(float(x))


def arr(xs):
    return "[" + ", ".join(num(x) for x in xs) + "]"


def write(name, stem, header, mtp, distances, lumped, tendon_half=(), passive_shift=(), smoothing=None,
          problem=(), top=()):
    osim = (OUT / name / f"{stem}.osim").read_text()
    coords = names(osim, "Coordinate")
    muscles = [m for tag in ("Thelen2003Muscle", "DeGrooteFregly2016Muscle", "Millard2012EquilibriumMuscle")
               for m in names(osim, tag)]
    passive = json.loads((REF / "joints/passive_moments.json").read_text())
    meta = json.loads((REF / "muscles/metabolic_parameters.json").read_text())["per_muscle_right_names"]
    lines = [header, f'geometry = "{stem}.geometry.json"'] + list(top) + [""]
    if problem:
        lines += ["[problem]"] + list(problem) + [""]
    limited = set()
    for j in passive["joints"]:
        cs = [c for c in j["applies_to"] if c in coords]
        if not cs:
            continue
        limited.update(cs)
        lines += ["[[passive_torques.table]]", "coordinates = [" + ", ".join(f'"{c}"' for c in cs) + "]",
                  f"k = {arr([j['k1'], j['k2'], j['k3'], j['k4']])}",
                  f"theta = {arr([j['theta_lower_rad'], j['theta_upper_rad']])}", "damping = 0.1", ""]
    mtps = [c for c in coords if c.startswith("mtp_angle")]
    if mtps and mtp is not None:
        limited.update(mtps)
        lines += ["[[passive_torques.table]]", "coordinates = [" + ", ".join(f'"{c}"' for c in mtps) + "]",
                  f"k = {arr(MTP_LIMIT['k'])}", f"theta = {arr(MTP_LIMIT['theta'])}",
                  f"damping = {num(mtp['damping'])}", ""]
    rest = [c for c in coords if c not in FLOATING and c not in limited]
    if rest:
        lines += ["[[passive_torques.table]]", "coordinates = [" + ", ".join(f'"{c}"' for c in rest) + "]",
                  "damping = 0.1", ""]
    if mtps and mtp is not None:
        for c in mtps:
            lines += ["[[coordinate_springs]]", f'coordinate = "{c}"', f"stiffness = {num(mtp['stiffness'])}", ""]
    for a, b, lo in distances:
        lines += ["[[distances]]", f'bodies = ["{a}", "{b}"]', f"min = {num(lo)}", ""]
    if tendon_half:
        lines += ["[[muscle_parameters]]", "match = [" + ", ".join(f'"{m}"' for m in tendon_half) + "]",
                  "tendon_stiffness_scale = 0.5", ""]
    if passive_shift:
        lines += ["[[muscle_parameters]]", "match = [" + ", ".join(f'"{m}"' for m in passive_shift) + "]",
                  "passive_fibre_shift = 0.9", ""]
    if smoothing is not None:
        lines += ["[metabolic]", f"smoothing = {num(smoothing)}", ""]
    lines.append("[metabolic.muscles]")
    for m in muscles:
        if m.endswith("_l") and m[:-2] + "_r" in muscles:
            continue
        if m in lumped:
            fst, sigma = lumped[m]
        elif m in meta:
            fst, sigma = meta[m]["slow_twitch_fraction"], meta[m]["specific_tension_MPa"]
        else:
            continue
        lines.append(f"{m} = {{ slow_twitch_fraction = {num(fst)}, specific_tension_mpa = {num(sigma)} }}")
    (OUT / name / f"{stem}.toml").write_text("\n".join(lines) + "\n")


HEAD = "# Settings of {what}, after PredSim ({src}).\n# Written by tools/models/predsim_settings.py; see docs/settings.md.\n# Contact spheres and actuators come from the .osim file."
write("falisse2022", "Falisse_et_al_2022",
      HEAD.format(what="Falisse_et_al_2022", src="settings_Falisse_et_al_2022.m: mtp k 25 N m/rad, B 2 N m s/rad"),
      {"stiffness": 25.0, "damping": 2.0}, DISTANCES_3D, {},
      problem=("# PredSim's mtp_type '2022paper': toes driven by their passive torque only;",
               "# the passive-torque cost counts the limit torques only.",
               'passive = { toes = "passive", cost = "limit" }',
               "# PredSim's bounds (and so scale factors) of every coordinate: its default table by name.",
               'bounds = "predsim"'))
write("dhondt2024", "DHondt_et_al_2024_4seg",
      HEAD.format(what="DHondt_et_al_2024_4seg", src="settings_DHondt_et_al_2024_4seg.m: mtp k 1 N m/rad,\n"
                  "# k_T x 0.5 for the calf muscles, passive fibre shift 0.9 for the shank and foot muscles,\n"
                  "# metabolic b = 100; ligament forces from the geometry file's ligament fits"),
      {"stiffness": 1.0, "damping": 0.1}, DISTANCES_3D, {}, ("soleus", "_gas"),
      ("soleus", "_gas", "per_", "tib_", "_dig_", "_hal_", "FDB"), 100.0,
      problem=("# PredSim's N for this model: 100 mesh intervals per half cycle.", "mesh_intervals = 100"),
      top=("# PredSim's IG_pelvis_y of this model (settings_DHondt_et_al_2024_4seg.m), not derived from it.",
           "standing_pelvis_height = 0.9385"))
write("gait1018", "gait1018",
      HEAD.format(what="gait1018 (2D)", src="settings_gait1018.m: no distance constraints"),
      None, [], LUMPED_2D, ("soleus", "gastroc"),
      problem=("# PredSim's default speed of this model (settings_gait1018.m); the passive-torque",
               "# cost counts the limit torques only, as PredSim's.", "speed = 1.25",
               'passive = { cost = "limit" }',
               "# PredSim's duration guess (0.65 s at 1.25 and 1.33 m/s).", 'guess_duration = "predsim"',
               "# PredSim's bounds (and so scale factors) of every coordinate: its default table by name.",
               'bounds = "predsim"'))
