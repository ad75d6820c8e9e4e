#!/usr/bin/env python3
"""scene_programs_test.py — the three reference programs with --scene and --stats.

    scene_programs_test.py BIN_DIR WORK_DIR

Writes small scene files into WORK_DIR, runs build/bin/<program>_ref on them
and checks, from the outside, what a user sees:
  - `--stats` prints one JSON object on stdout whose stages and counters are
    the ones the scene calls for (numbers worked out by hand below);
  - command-line flags override the scene (--shader, --aa, --size);
  - a broken scene file exits with status 2, names the file and the key path
    on stderr, and writes no output file.
Exit status 0 when every check passes; each failure is printed.
"""
import json
import os
import struct
import subprocess
import sys

BIN, WORK = sys.argv[1], sys.argv[2]
os.makedirs(WORK, exist_ok=True)
failures = []

def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)

def write(name, text):
    path = os.path.join(WORK, name)
    with open(path, "w") as f:
        f.write(text)
    return path

def run(program, args, env_extra=None):
    env = dict(os.environ)
    env.update(env_extra or {})
    p = subprocess.run([os.path.join(BIN, program)] + args, capture_output=True, text=True,
                       env=env, timeout=120)
    return p.returncode, p.stdout, p.stderr

def stats_of(program, args, env_extra=None):
    out = os.path.join(WORK, program + ".png")
    if os.path.exists(out):
        os.remove(out)
    code, stdout, stderr = run(program, args + ["--stats", "-o", out], env_extra)
    check(code == 0, f"{program} {' '.join(args)}: exit {code}, stderr: {stderr.strip()}")
    try:
        stats = json.loads(stdout)
    except ValueError as e:
        check(False, f"{program} {' '.join(args)}: --stats is not one JSON object ({e}): {stdout!r}")
        return {}, out
    return stats, out

def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    return struct.unpack(">II", head[16:24])  # IHDR width, height

def stages(s):
    return set(s.get("stages_run", []))

# A 64×48 frame that one triangle covers completely: seen from (0,0,5) with
# a 45° field of view, the plane z = 0 shows ±2.071 units vertically (±2.76
# horizontally at aspect 4:3); the triangle's edges pass outside that box
# (the left edge is at x = -5.10 where y = 2.071), and its corners stay inside
# the guard band (|x_ndc| <= 3.3), so one triangle covers every pixel once:
# 64 · 48 = 3072 fragments without AA.
PIXELS = 64 * 48
SCENE = """{
  "image": {"width": 64, "height": 48},
  "camera": {"eye": [0, 0, 5], "fov_deg": 45, "near": 0.1, "far": 50},
  "objects": [{"name": "wall", "shape": "triangle",
               "vertices": [[-9, -4, 0], [9, -4, 0], [0, 10, 0]],
               "material": {"texture": {"builtin": "checker", "size": 32, "squares": 4}}}],
  "lights": [{"position": [2, 3, 4], "intensity": 20}],
  "shader": "texture",
  "filter": "bilinear"
}
"""
small = write("small.json", SCENE)

# ---- hw3: the scene's effects, then flags over them ----------------------------
# The teaching pipeline (the default), whose buffer_bytes is the frame's
# colour + depth (12 + 4 bytes per sample); the fast renderer reports its tiles.
s, out = stats_of("hw3_shading_ref", ["--scene", small])
if s:
    check(stages(s) == {"vertex", "clip", "setup", "raster", "fragment", "texture", "lighting"},
          f"hw3 textured scene: stages {sorted(stages(s))}")
    check(s["fragments_shaded"] == PIXELS, f"hw3: {s['fragments_shaded']} fragments, expected {PIXELS}")
    check(s["texels_fetched"] == 4 * PIXELS, f"hw3 bilinear: {s['texels_fetched']} texels, expected 4 per fragment")
    check(s["lighting_evaluations"] == PIXELS, "hw3: one light, one evaluation per fragment")
    check(s["varyings_interpolated"] == 3 * PIXELS, "hw3 texture shader: normal, view position and UV")
    check(s["mip_levels_built"] == 0, "hw3 bilinear builds no mip levels")
    check(s["buffer_bytes"] == PIXELS * 16, f"hw3 no AA: buffer_bytes {s['buffer_bytes']}, expected {PIXELS * 16}")
    check(png_size(out) == (64, 48), "hw3 writes the scene's 64x48")
# the same through the fast renderer: the same work (buffers aside)
f, _ = stats_of("hw3_shading_ref", ["--scene", small, "--renderer", "fast"])
if s and f:
    for key in ("stages_run", "fragments_shaded", "texels_fetched", "varyings_interpolated",
                "samples_tested", "lighting_evaluations"):
        check(f[key] == s[key], f"hw3 fast path {key}: {f[key]} vs plain {s[key]}")
# --shader overrides the scene's: the normal shader reads no texture, no light
s, _ = stats_of("hw3_shading_ref", ["--scene", small, "--shader", "normal"])
if s:
    check(stages(s) == {"vertex", "clip", "setup", "raster", "fragment"},
          f"hw3 --shader normal: stages {sorted(stages(s))}")
    check(s["texels_fetched"] == 0 and s["lighting_evaluations"] == 0,
          "hw3 --shader normal fetches no texel and lights nothing")
    check(s["varyings_interpolated"] == PIXELS, "hw3 --shader normal interpolates the normal only")
# --filter trilinear: mip levels of the 32×32 map (16, 8, 4, 2, 1) and 8 taps
s, _ = stats_of("hw3_shading_ref", ["--scene", small, "--filter", "trilinear"])
if s:
    check(s["mip_levels_built"] == 5 and "mipmap" in stages(s), f"hw3 trilinear: {s['mip_levels_built']} mip levels, expected 5")
    check(s["texels_fetched"] == 8 * PIXELS, "hw3 trilinear: 8 texels per fragment")
# --aa msaa and --size override the scene: 4 samples, shaded once per pixel
s, out = stats_of("hw3_shading_ref", ["--scene", small, "--aa", "msaa", "--size", "32x24"])
if s:
    px = 32 * 24
    check("resolve" in stages(s), "hw3 --aa msaa resolves")
    check(s["samples_covered"] == 4 * px and s["fragments_shaded"] == px,
          f"hw3 msaa 32x24: {s['samples_covered']} samples covered, {s['fragments_shaded']} shaded")
    check(s["buffer_bytes"] == 4 * px * 16, f"hw3 msaa 32x24: buffer_bytes {s['buffer_bytes']}")
    check(png_size(out) == (32, 24), "hw3 --size 32x24")

# ---- hw2: flat colours, no AA unless asked ------------------------------------
s, _ = stats_of("hw2_rasterize_ref", ["--scene", small])
if s:
    check(stages(s) == {"vertex", "clip", "setup", "raster"}, f"hw2: stages {sorted(stages(s))}")
    check(s["samples_covered"] == PIXELS and s["texels_fetched"] == 0, "hw2: every pixel, no texels")
    check(s["buffer_bytes"] == PIXELS * 16, f"hw2 no AA: buffer_bytes {s['buffer_bytes']}")
s, _ = stats_of("hw2_rasterize_ref", ["--scene", small, "--aa", "ssaa"])
if s:
    check(s["fragments_shaded"] == 4 * PIXELS and "resolve" in stages(s), "hw2 --aa ssaa shades every sample")

# ---- hw1: a wireframe, three lines per triangle ---------------------------------
s, _ = stats_of("hw1_transform_ref", ["--scene", small, "-r", "10"])
if s:
    check(stages(s) == {"vertex", "clip", "setup", "wireframe"}, f"hw1: stages {sorted(stages(s))}")
    check(s["lines_drawn"] == 3 and s["samples_tested"] == 0, "hw1: 3 lines, no rasterizer")

# ---- broken scenes: exit 2, file and key path named, nothing written ------------
broken = write("broken.json", SCENE.replace('"filter": "bilinear"', '"filter": "bilinear", "aa": {"mode": "msaa", "samples": 3}'))
missing_map = write("missing_map.json", SCENE.replace('{"builtin": "checker", "size": 32, "squares": 4}', '"no_such_texture.png"'))
cases = [(broken, "broken.json: aa.samples:"), (missing_map, "objects[0].material.texture: cannot load"),
         (os.path.join(WORK, "no_such_scene.json"), "no_such_scene.json: cannot open the scene file")]
for program in ("hw1_transform_ref", "hw2_rasterize_ref", "hw3_shading_ref"):
    for path, expected in cases:
        if path == missing_map and program != "hw3_shading_ref":
            # Only what a program draws is loaded: hw1 and hw2 draw
            # flat colours and never open the map.
            out = os.path.join(WORK, "flat.png")
            code, stdout, stderr = run(program, ["--scene", path, "-o", out])
            check(code == 0 and os.path.exists(out),
                  f"{program} --scene missing_map.json: exit {code}, expected 0 (a map it does "
                  f"not draw): {stderr.strip()!r}")
            continue
        out = os.path.join(WORK, "must_not_exist.png")
        if os.path.exists(out):
            os.remove(out)
        code, stdout, stderr = run(program, ["--scene", path, "--stats", "-o", out])
        name = os.path.basename(path)
        check(code == 2, f"{program} --scene {name}: exit {code}, expected 2")
        check(expected in stderr, f"{program} --scene {name}: stderr {stderr.strip()!r} lacks {expected!r}")
        check(not os.path.exists(out), f"{program} --scene {name}: wrote {out}")
        check(stdout == "", f"{program} --scene {name}: printed stats for a scene that did not load")

print(f"scene_programs_test: {len(failures)} failure(s)")
sys.exit(1 if failures else 0)
