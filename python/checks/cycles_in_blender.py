"""Runs stfit's Cycles exports inside Blender's own Python API: every material function of every
given file is called, and the node it connects to the material output is checked to be the
Glass or Principled BSDF with the distribution, Roughness and IOR the file's comment states.
What it proves is that the scripts run against Blender's real node and input names.

Usage (a Python 3.11 with Blender as a module, `pip install bpy`, about 1 GB, so not part of
.ci/run):

    stfit export fits/example-fits.json --to cycles --out /tmp/cycles/
    python python/checks/cycles_in_blender.py /tmp/cycles/*-cycles.py
"""

import re
import sys

import bpy

failures = 0
materials = 0
for path in sys.argv[1:]:
    text = open(path).read()
    namespace = {}
    exec(compile(text, path, "exec"), namespace)
    stated = {float(r) for r in re.findall(r'"Roughness"\]\.default_value = ([0-9.e-]+)', text)}
    for name, fn in list(namespace.items()):
        if not (callable(fn) and (name.endswith("_glass") or name.endswith("_principled"))):
            continue
        mat = fn()
        materials += 1
        out = mat.node_tree.nodes.get("Material Output")
        links = out.inputs["Surface"].links
        node = links[0].from_node if links else None
        kind = node.bl_idname if node else None
        expected = "ShaderNodeBsdfGlass" if name.endswith("_glass") else "ShaderNodeBsdfPrincipled"
        roughness = node.inputs["Roughness"].default_value if node else None
        ok = (kind == expected and any(abs(roughness - r) < 1e-6 for r in stated)
              and node.inputs["IOR"].default_value > 1.0)
        failures += not ok
        print(f"{'ok ' if ok else 'BAD'} {name}: {kind} {node.distribution if node else ''} "
              f"Roughness {roughness:.6f} IOR {node.inputs['IOR'].default_value:.4f}")
print(f"Blender {bpy.app.version_string}: {materials} materials, {failures} failed")
sys.exit(1 if failures or materials == 0 else 0)
