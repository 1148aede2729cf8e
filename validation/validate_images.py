#!/usr/bin/env python3
"""Compares fly's images with Blender Cycles renders of the same camera, per material region, as luminance in
cd/m²; docs/validation.md ("Images against Cycles") describes the method and records the results.

  validation/validate_images.py [VIEW ...] [--out DIR] [--fly build/cli/fly] [--size 320x180]
      [--cycles-samples 256] [--bake-target 2%] [--bake-time 3m] [--threads 0] [--images docs/images]

With no VIEW it runs every view (`--list` names them). For each view's scene it writes, under DIR/SCENE/, the
scene file both programs read (every material Lambertian with its glTF base colour, textures kept, except
clear glass, which stays fly's thin pane; goniometric lights left out, which the Cycles reference lacks) and
fly's bake of it (`fly bake`); for each view, under DIR/VIEW/: fly's light-map and sunlight images
(`fly render --mode lightmap|sunlight`, EXR in cd/m²), fly's sky and sun (`fly sky --scene`), two Cycles
renders with different seeds (validation/cycles_irradiance.py `render`: the same camera and size, fly's sky
image as the world and its sun as a sun lamp, a material-index pass), regions.csv and result.json; the
side-by-side picture (fly light-map | fly sunlight | Cycles, one exposure) as DIR/VIEW/side-by-side.png and,
with --images, IMAGES/cycles-VIEW.png; DIR/summary.md gathers the tables.

Regions: the pixels whose whole 3 × 3 neighbourhood in Cycles' material-index pass is one material (edges
and anti-aliased pixels left out). Per region: the mean luminance of each image; Cycles' value is the mean of
its two seeds, with the standard error of that mean from the per-pixel differences of the seeds (pixels are
independent estimates: σ² = Σ (a − b)² / (4 n²)). A diffuse region agrees when |L_fly − L_Cycles| ≤
tolerance × L_Cycles + 3σ, the tolerance 5 % in light-map mode and 10 % in sunlight mode.

Needs Python 3 (standard library only), Blender (Debian 12's `blender` 3.4 with python3-numpy) and
OpenImageIO's `oiiotool` (to read EXR files). Third-party models are read from $FLY_MODELS as in validate.py, which
here also holds godot/living_room.glb (Godot's demo `3d/physical_light_camera_units/living_room.glb`).
"""
import argparse
import array
import json
import math
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import scene_files  # noqa: E402
import validate  # noqa: E402

TOLERANCE = {"lightmap": 0.05, "sunlight": 0.10}
SIGMAS = 3.0
REC709_Y = (0.2126, 0.7152, 0.0722)
MIN_REGION_PIXELS = 20
HELSINKI = {"latitude": 60.17, "longitude": 24.94, "elevation": 15, "timeZone": "Europe/Helsinki", "northAngle": 0}


# ---------------------------------------------------------------------------------------------------------
# Scenes. Each returns a fly scene dict (paths absolute); the driver makes its materials Lambertian.

def scene_house(work):
    """The repository's house (scenes/house/house.json): clear sky and sun in Helsinki on 21 June at 15:00,
    clear-glass windows; its IES downlight is left out (the Cycles reference has no goniometric lights)."""
    path = os.path.join(ROOT, "scenes", "house", "house.json")
    with open(path) as f:
        scene = json.load(f)
    for m in scene["models"]:
        m["file"] = os.path.join(os.path.dirname(path), m["file"])
    scene["lights"] = [light for light in scene.get("lights", []) if light.get("type") != "ies"]
    scene["bake"] = {k: v for k, v in scene.get("bake", {}).items() if k in ("texelsPerMetre", "lightTextures")}
    return scene


def scene_living_room(work):
    """Godot's living room (its physical-light demo: a room with a two-pane window opening, no glass, onto a
    walled yard) under fly's clear sky at 53.4° N on 21 June at 12:00 UTC, seen from the demo's camera."""
    return {"fly": 1, "models": [{"file": validate.model("godot/living_room.glb"), "name": "room"}],
            "site": {"latitude": 53.4, "longitude": 0.0, "elevation": 0, "timeZone": "UTC", "northAngle": 0},
            "time": "2026-06-21T12:00", "sky": {"model": "clear", "sun": True, "turbidity": 3.0},
            "cameras": [{"name": "godot", "position": [-2.93199, 2.20651, -1.8947], "target": [0.5, 1.2, 1.5],
                         "up": [0, 1, 0], "fovDeg": 51.28, "near": 0.05, "far": 200}]}


def scene_box_textured(work):
    """Khronos' BoxTextured (a 1 m cube with the Cesium logo as base-colour texture) standing on a 6 m floor
    of albedo 0.5, in the house's daylight (Helsinki, 21 June 15:00, clear sky and sun)."""
    floor, floor_uv = scene_files.quad((0, 0, 0), 3, 3, (0, 0, 1), (1, 0, 0))
    scene_files.write_gltf(os.path.join(work, "floor.gltf"),
                           [{"name": "Floor", "triangles": floor, "uvs": floor_uv, "material": 0}],
                           [{"name": "Floor", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1],
                                                                      "metallicFactor": 0}}])
    return {"fly": 1,
            "models": [{"file": validate.model("khronos/BoxTextured/glTF/BoxTextured.gltf"), "name": "box",
                        "translation": [0, 0.5, 0]},
                       {"file": os.path.join(work, "floor.gltf"), "name": "floor"}],
            "site": HELSINKI, "time": "2026-06-21T15:00", "sky": {"model": "clear", "sun": True, "turbidity": 3.0},
            "bake": {"texelsPerMetre": 40},
            "cameras": [{"name": "product", "position": [1.9, 1.4, 2.3], "target": [0, 0.45, 0], "up": [0, 1, 0],
                         "fovDeg": 40, "near": 0.05, "far": 100}]}


def scene_cornell_box(work):
    """The repository's Cornell box (scenes/cornell-box/cornell-box.json, Cornell's data: a 10 000 cd/m²
    ceiling panel, no daylight)."""
    path = os.path.join(ROOT, "scenes", "cornell-box", "cornell-box.json")
    with open(path) as f:
        scene = json.load(f)
    for m in scene["models"]:
        m["file"] = os.path.join(os.path.dirname(path), m["file"])
    scene["bake"] = {k: v for k, v in scene.get("bake", {}).items() if k == "texelsPerMetre"}
    return scene


SCENES = {"house": scene_house, "living-room": scene_living_room, "box-textured": scene_box_textured,
          "cornell-box": scene_cornell_box}
VIEWS = {"house-interior": ("house", "interior"), "house-street": ("house", "street"),
         "living-room": ("living-room", "godot"), "box-textured": ("box-textured", "product"),
         "cornell-box": ("cornell-box", "classic")}


def lambertian(scene, work):
    """Every material Lambertian with its base colour (textures kept), as validate.py's cases, except those the
    scene makes clear glass, which both programs treat as a thin Fresnel pane."""
    glass = [o for o in scene.get("overrides", []) if o.get("preset") == "clear-glass"]
    names = {o["material"] for o in glass}
    rest = [o for o in scene_files.lambertian_overrides(scene, work) if o["material"] not in names]
    scene["overrides"] = [{"material": o["material"], "preset": "clear-glass"} for o in glass] + rest
    return scene


# ---------------------------------------------------------------------------------------------------------
# Images: EXR pixels as oiiotool prints them (--dumpdata: "Pixel (x, y): v v v", rows top-down).

def exr_channels(exr, channels=None):
    """(width, height, values): the image's channels (all, or those named), interleaved, rows top-down."""
    out = subprocess.run(["oiiotool", "-v", "--info", "--dumpdata", exr], check=True, capture_output=True,
                         text=True).stdout.splitlines()
    width = height = None
    names = []
    values = array.array("f")
    for line in out:
        text = line.strip()
        if width is None and " x " in text and "channel" in text:
            size = text.rsplit(":", 1)[1].split(",")[0].split("x")
            width, height = int(size[0]), int(size[1])
        elif text.startswith("channel list:"):
            names = [c.strip() for c in text.split(":", 1)[1].split(",")]
            pick = [names.index(c) for c in channels] if channels else list(range(len(names)))
        elif text.startswith("Pixel ("):
            v = text.split(":", 1)[1].split()
            values.extend(float(v[k]) for k in pick)
    if width is None or len(values) != width * height * len(pick):
        raise SystemExit(f"validate_images: cannot read {exr} with oiiotool")
    return width, height, values


def luminance(rgb):
    return [REC709_Y[0] * rgb[3 * i] + REC709_Y[1] * rgb[3 * i + 1] + REC709_Y[2] * rgb[3 * i + 2]
            for i in range(len(rgb) // 3)]


def cycles_image(exr):
    layer = "ViewLayer."
    _, _, rgb = exr_channels(exr, [layer + "Combined." + c for c in "RGB"])
    w, h, index = exr_channels(exr, [layer + "IndexMA.X"])
    return w, h, rgb, [int(round(v)) for v in index]


def interior_regions(index, width, height):
    """Pixel lists of each material whose 3 × 3 neighbourhood is all that material (index 0: no surface)."""
    regions = {}
    for y in range(1, height - 1):
        for x in range(1, width - 1):
            k = index[y * width + x]
            if k == 0:
                continue
            if all(index[(y + dy) * width + x + dx] == k for dy in (-1, 0, 1) for dx in (-1, 0, 1)):
                regions.setdefault(k, []).append(y * width + x)
    return regions


# ---------------------------------------------------------------------------------------------------------
# The side-by-side picture: one exposure for all panels, set by Cycles' log-average luminance (key 0.18),
# Reinhard's L/(1+L) on luminance with the colour kept, then sRGB.

def srgb8(v):
    v = max(0.0, min(1.0, v))
    return int(round(255 * (12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055)))


def tone_map(rgb, scale):
    out = bytearray()
    for i in range(len(rgb) // 3):
        r, g, b = (scale * rgb[3 * i + k] for k in range(3))
        y = REC709_Y[0] * r + REC709_Y[1] * g + REC709_Y[2] * b
        f = 1.0 / (1.0 + y) if y > 0 else 0.0
        out += bytes((srgb8(r * f), srgb8(g * f), srgb8(b * f)))
    return out


def side_by_side(path, width, height, panels, scale):
    gap = 4
    total = len(panels) * width + (len(panels) - 1) * gap
    mapped = [tone_map(p, scale) for p in panels]

    def pixel(x, y):
        k, u = divmod(x, width + gap)
        if u >= width:
            return (255, 255, 255, 255)
        o = 3 * (y * width + u)
        return (mapped[k][o], mapped[k][o + 1], mapped[k][o + 2], 255)
    scene_files.write_png_rgba(path, total, height, pixel)


# ---------------------------------------------------------------------------------------------------------

def run_view(view, args, baked):
    scene_name, camera = VIEWS[view]
    scene_dir = os.path.join(args.out, scene_name)
    work = os.path.join(args.out, view)
    os.makedirs(scene_dir, exist_ok=True)
    os.makedirs(work, exist_ok=True)
    scene_path = os.path.join(scene_dir, "scene.json")
    bake_dir = os.path.join(scene_dir, "bake")
    times = {}
    if scene_name not in baked:
        scene = lambertian(SCENES[scene_name](scene_dir), scene_dir)
        with open(scene_path, "w") as f:
            json.dump(scene, f, indent=1)
        if not (args.reuse_bake and os.path.isdir(bake_dir)):
            baked[scene_name] = validate.run(
                [args.fly, "bake", scene_path, "--out", bake_dir, "--target-error", args.bake_target,
                 "--time", args.bake_time, "--threads", str(args.threads)], os.path.join(scene_dir, "bake.log"))
        else:
            baked[scene_name] = None
    times["bake_s"] = baked[scene_name]
    with open(scene_path) as f:
        scene = json.load(f)
    size = f"{args.width}x{args.height}"
    fly_images = {}
    daylight = scene.get("sky", {}).get("model", "none") != "none" or scene.get("sky", {}).get("sun", False)
    modes = ("lightmap", "sunlight") if daylight else ("lightmap",)  # sunlight mode draws the sky and sun only
    for mode in modes:
        exr = os.path.join(work, f"fly-{mode}.exr")
        times[f"fly_{mode}_s"] = validate.run([args.fly, "render", bake_dir, "--camera", camera, "--mode", mode,
                                               "--size", size, "--out", exr], os.path.join(work, f"fly-{mode}.log"))
        w, h, rgb = exr_channels(exr)
        if (w, h) != (args.width, args.height):
            raise SystemExit(f"validate_images: {exr} is {w}×{h}, not {size}")
        fly_images[mode] = rgb
    sky_args = []
    if daylight:
        sky_exr, sky_json = os.path.join(work, "sky.exr"), os.path.join(work, "sky.json")
        with open(sky_json, "w") as f:
            subprocess.run([args.fly, "sky", "--scene", scene_path, "--out", sky_exr, "--size", "1024", "--json"],
                           stdout=f, check=True)
        sky_args = ["--sky", sky_exr, "--sky-json", sky_json]
    seeds = []
    for seed in (args.seed, args.seed + 1):
        exr = os.path.join(work, f"cycles-seed{seed}.exr")
        info_path = os.path.join(work, f"cycles-seed{seed}.json")
        times[f"cycles_seed{seed}_s"] = validate.run(validate.blender_cmd(
            args, "render", "--scene", scene_path, "--camera", camera, "--out", exr, "--info", info_path,
            "--width", args.width, "--height", args.height, "--samples", args.cycles_samples, "--seed", seed,
            "--threads", args.threads, *sky_args), os.path.join(work, f"cycles-seed{seed}.log"))
        with open(info_path) as f:
            info = json.load(f)
        w, h, rgb, index = cycles_image(exr)
        seeds.append((rgb, index, info))
    (rgb_a, index, info), (rgb_b, _, _) = seeds
    cycles_rgb = array.array("f", ((a + b) / 2 for a, b in zip(rgb_a, rgb_b)))
    lum = {"cycles_a": luminance(rgb_a), "cycles_b": luminance(rgb_b)}
    for mode, rgb in fly_images.items():
        lum[mode] = luminance(rgb)
    names = {k: name for name, k in info["regions"].items()}
    kinds = {}
    for m in info["materials"]:
        base = m["name"][:-4] if len(m["name"]) > 4 and m["name"][-4] == "." and m["name"][-3:].isdigit() else m["name"]
        if m.get("preset") == "clear-glass":
            kinds[base] = "clear glass"
        elif any(c > 0 for c in m.get("emission", [])):
            kinds[base] = "emitter"
        else:
            kinds.setdefault(base, "diffuse")
    rows = []
    for k, pixels in sorted(interior_regions(index, args.width, args.height).items()):
        if len(pixels) < MIN_REGION_PIXELS:
            continue
        n = len(pixels)
        a = sum(lum["cycles_a"][p] for p in pixels) / n
        b = sum(lum["cycles_b"][p] for p in pixels) / n
        sigma = math.sqrt(sum((lum["cycles_a"][p] - lum["cycles_b"][p]) ** 2 for p in pixels)) / (2 * n)
        cyc = (a + b) / 2
        name = names.get(k, f"#{k}")
        row = {"region": name, "kind": kinds.get(name, "diffuse"), "pixels": n, "cycles": cyc,
               "cycles_sigma": sigma, "cycles_seed_difference": a - b}
        for mode in ("lightmap", "sunlight"):
            if mode not in lum:
                row.update({mode: None, mode + "_rel": None, mode + "_within": None})
                continue
            fly = sum(lum[mode][p] for p in pixels) / n
            row[mode] = fly
            row[mode + "_rel"] = (fly - cyc) / cyc if cyc > 0 else None
            row[mode + "_within"] = (abs(fly - cyc) <= TOLERANCE[mode] * cyc + SIGMAS * sigma
                                     if row["kind"] == "diffuse" else None)
        rows.append(row)
    with open(os.path.join(work, "regions.csv"), "w") as f:
        keys = list(rows[0])
        f.write(",".join(keys) + "\n")
        for r in rows:
            f.write(",".join(f"{r[k]:.6g}" if isinstance(r[k], float) else "" if r[k] is None else str(r[k])
                             for k in keys) + "\n")
    # One exposure for the three panels, from Cycles' log-average luminance over the surfaces.
    logs = [math.log(max(lum["cycles_a"][i], 1e-4)) for i in range(len(index)) if index[i] > 0]
    key = math.exp(sum(logs) / len(logs)) if logs else 1.0
    scale = 0.18 / key
    picture = os.path.join(work, "side-by-side.png")
    side_by_side(picture, args.width, args.height, [fly_images[m] for m in modes] + [cycles_rgb], scale)
    if args.images:
        shutil.copyfile(picture, os.path.join(args.images, f"cycles-{view}.png"))
    result = {"view": view, "scene": scene_name, "camera": camera, "size": size,
              "cycles_samples": args.cycles_samples, "regions": rows, "times": times,
              "cycles_render_s": [s[2]["render_s"] for s in seeds], "sky": info.get("sky"),
              "exposure_key_cd_m2": key, "fly_commit": args.commit}
    with open(os.path.join(work, "result.json"), "w") as f:
        json.dump(result, f, indent=1)
    text = format_view(result)
    print(text)
    return result


def format_view(res):
    t = res["times"]
    bake = "reused" if t.get("bake_s") is None else f"{t['bake_s']:.0f} s"
    cyc = " + ".join(f"{s:.0f}" for s in res["cycles_render_s"])
    lines = [f"### {res['view']}", "",
             f"fly at {res['fly_commit']}; camera '{res['camera']}', {res['size']}; bake {bake}; fly renders "
             f"{t['fly_lightmap_s']:.1f} s (light-map)"
             f"{'' if 'fly_sunlight_s' not in t else ' and %.1f s (sunlight)' % t['fly_sunlight_s']}; Cycles "
             f"{res['cycles_samples']} samples per pixel, two seeds, {cyc} s of rendering", "",
             "| region | kind | pixels | Cycles cd/m² ± σ | fly light-map | diff. | within 5 % + 3σ | fly sunlight "
             "| diff. | within 10 % + 3σ |", "|---|---|---|---|---|---|---|---|---|---|"]

    def verdict(v):
        return "—" if v is None else ("yes" if v else "**no**")

    def pct(v):
        return "—" if v is None else f"{100 * v:+.1f} %"
    def value(v):
        return "—" if v is None else f"{v:.4g}"
    for r in res["regions"]:
        lines.append(f"| {r['region']} | {r['kind']} | {r['pixels']} | {r['cycles']:.4g} ± {r['cycles_sigma']:.2g} | "
                     f"{value(r['lightmap'])} | {pct(r['lightmap_rel'])} | {verdict(r['lightmap_within'])} | "
                     f"{value(r['sunlight'])} | {pct(r['sunlight_rel'])} | {verdict(r['sunlight_within'])} |")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("views", nargs="*", help="views to run (default: all)")
    ap.add_argument("--list", action="store_true", help="print the views and exit")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "validation-images"))
    ap.add_argument("--fly", default=os.path.join(ROOT, "build", "cli", "fly"))
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--size", default="320x180", help="image size WIDTHxHEIGHT of both programs")
    ap.add_argument("--cycles-samples", type=int, default=256, help="Cycles samples per pixel, each seed")
    ap.add_argument("--seed", type=int, default=0, help="Cycles' first seed (the second is SEED + 1)")
    ap.add_argument("--bake-target", default="2%", help="fly bake's --target-error")
    ap.add_argument("--bake-time", default="3m", help="fly bake's run-time limit")
    ap.add_argument("--reuse-bake", action="store_true", help="keep an earlier run's bake of a scene")
    ap.add_argument("--threads", type=int, default=0, help="threads for both (0: all cores)")
    ap.add_argument("--images", help="also copy each side-by-side picture here as cycles-VIEW.png")
    args = ap.parse_args()
    if args.list:
        for name, (scene, camera) in VIEWS.items():
            doc = " ".join((SCENES[scene].__doc__ or "").split())
            print(f"{name}: camera '{camera}' of {doc.split('. ')[0].rstrip('.')}.")
        return
    names = args.views or list(VIEWS)
    for n in names:
        if n not in VIEWS:
            raise SystemExit(f"validate_images: unknown view '{n}'; views: {', '.join(VIEWS)}")
    args.width, args.height = (int(v) for v in args.size.lower().split("x"))
    args.fly = validate.FLY = os.path.abspath(args.fly)
    if not os.path.exists(args.fly):
        raise SystemExit(f"validate_images: {args.fly} not found; build fly first (./scripts/build)")
    args.out = os.path.abspath(args.out)
    os.makedirs(args.out, exist_ok=True)
    version = subprocess.run([args.fly, "--version"], capture_output=True, text=True).stdout.strip()
    head = subprocess.run(["git", "-C", ROOT, "log", "-1", "--format=%h"], capture_output=True, text=True).stdout
    args.commit = f"{version} ({args.fly}; harness at {head.strip()})"
    baked = {}
    results = [run_view(n, args, baked) for n in names]
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        for r in results:
            f.write(format_view(r) + "\n")


if __name__ == "__main__":
    main()
