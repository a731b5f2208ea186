#!/usr/bin/env python3
"""Writes cornell.rad, the Cornell box of testdata/obj/cornell.obj (and scenes/cornell) as a
Radiance scene: one polygon per OBJ face, its materials as spec-free `plastic` (Lambertian,
two-sided, as the OBJ's) and the ceiling light as a `light` of the OBJ's Ke. Coordinates are
copied as they are (+y up: a .rad file's axes are not converted). Run from this folder."""
import pathlib

here = pathlib.Path(__file__).parent
obj = (here / "../obj/cornell.obj").read_text().splitlines()
kd = {
    "white": "0.885809 0.698859 0.666422",
    "red": "0.570068 0.0430135 0.0443706",
    "green": "0.105421 0.37798 0.076425",
}
out = [
    "# The Cornell box of testdata/obj/cornell.obj as a Radiance scene, written by make_cornell.py:",
    "# one polygon per face, Lambertian plastics and the ceiling light's radiance in W/(sr m^2).",
    "# Axes as in the OBJ (+y up).",
    "",
]
for name, c in kd.items():
    out += [f"void plastic {name}", "0", "0", f"5 {c} 0 0", ""]
out += ["void light light", "0", "0", "3 18.387 13.9873 6.75357", ""]
vertices, material, count = [], None, 0
for line in obj:
    w = line.split()
    if not w:
        continue
    if w[0] == "v":
        vertices.append(w[1:4])
    elif w[0] == "usemtl":
        material = w[1]
    elif w[0] == "f":
        corners = [vertices[int(c.split("/")[0]) - 1] for c in w[1:]]
        out += [f"{material} polygon {material}_{count}", "0", "0", f"{3 * len(corners)}"]
        out += ["  " + " ".join(v) for v in corners]
        out.append("")
        count += 1
(here / "cornell.rad").write_text("\n".join(out))
