#!/usr/bin/env python3
"""Compares `fly illuminance` with Blender Cycles (and with exact answers where they exist) at the same
sensors of the same scenes; docs/validation.md describes the method and records the results.

  validation/validate.py [CASE ...] [--out DIR] [--fly build/cli/fly] [--cycles-samples 256] ...

With no CASE it runs every case (`--list` names them). For each case it writes, under DIR/CASE/: the fly
scene file (the Lambertian form: every material diffuse only), the sensors, fly's and Cycles' CSV output,
compare.csv (one row per sensor: both estimates, their standard errors, the exact value where known, the
relative difference and whether it lies within the tolerance) and the logs; it prints the agreement by
sensor group, and DIR/summary.md gathers the tables of all cases run.

Agreement: a sensor agrees when |E_fly − E_cycles| ≤ 3σ + 2 % E_cycles, σ = √(σ_fly² + σ_cycles²), the
combined standard error of both estimates. Needs Python 3 (standard library only) and Blender (Debian 12's
`blender` 3.4, with its glTF importer).
"""
import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import scene_files  # noqa: E402

def model(relative):
    """A third-party model under $FLY_MODELS: a folder holding khronos/ (the Khronos glTF sample models) and
    bevy/ (the Bevy engine's example assets), which the repository does not contain."""
    base = os.environ.get("FLY_MODELS")
    if not base:
        raise SystemExit("validate: set FLY_MODELS to the folder that holds khronos/ and bevy/ (the Khronos glTF "
                         "sample models and Bevy's example assets) for the third-party cases")
    path = os.path.join(base, relative)
    if not os.path.exists(path):
        raise SystemExit(f"validate: {path} not found (FLY_MODELS={base})")
    return path
FLY = os.path.join(ROOT, "build", "cli", "fly")  # --fly
TOLERANCE_SIGMAS = 3.0
TOLERANCE_RELATIVE = 0.02


# ---------------------------------------------------------------------------------------------------------
# Cases. Each returns {"scene": fly scene dict, "sensors": [(x, y, z, nx, ny, nz, group)] or "cast": {...},
# "exact": optional function(row) -> lux}.

def case_plane_sun(work):
    """A 2 km square of albedo 0.5 (one-sided, facing up) under a directional light of 1000 lx from 60° off
    the zenith, towards −x. Exact (the plane is effectively infinite: 1 km ≫ the sensors' 1 m height):
    facing up E = E_n cos θ; facing the sun's azimuth, vertical E = E_n sin θ + ρ E_n cos θ / 2 (half the
    ground's radiance ρ E_n cos θ / π times π); facing down E = ρ E_n cos θ."""
    rho, en, theta = 0.5, 1000.0, math.radians(60.0)
    tris, uvs = scene_files.quad((0, 0, 0), 1000, 1000, (0, 0, 1), (1, 0, 0))
    scene_files.write_gltf(os.path.join(work, "plane.gltf"), [{"name": "Ground", "triangles": tris,
                                                                "material": 0}],
                           [{"name": "Ground", "pbrMetallicRoughness": {"baseColorFactor": [rho, rho, rho, 1],
                                                                       "metallicFactor": 0}}])
    direction = [math.sin(theta), -math.cos(theta), 0.0]  # travels towards +x and down: the sun is at −x
    scene = {"fly": 1, "models": [{"file": os.path.join(work, "plane.gltf")}],
             "lights": [{"name": "sun", "type": "directional", "direction": direction, "intensity": en}]}
    sensors, exact = [], {}
    for i, (x, z) in enumerate([(0, 0), (3, -2), (-5, 4), (10, 10)]):
        for group, n, e in (("up", (0, 1, 0), en * math.cos(theta)),
                            ("towards-sun", (-1, 0, 0), en * math.sin(theta) + rho * en * math.cos(theta) / 2),
                            ("down", (0, -1, 0), rho * en * math.cos(theta))):
            sensors.append((x, 1.0, z) + n + (group,))
            exact[len(sensors) - 1] = e
    return {"scene": scene, "sensors": sensors, "exact": exact}


def case_sphere_point(work, rho):
    """A closed sphere of radius 1 m and albedo ρ (one-sided, front faces inward; 256 × 128 segments, so its
    facets lie within 0.008 % of the radius) with a 100 cd point light at its centre. The walls' radiosity is
    uniform, B = ρ E_wall, so E_wall = I/R² + ρ E_wall, E_wall = I / (R² (1 − ρ)); every inner point sees the
    walls' uniform radiance B/π on its whole hemisphere, so a sensor at distance d from the light facing at
    angle α from it gets E = I max(cos α, 0) / d² + ρ I / (R² (1 − ρ))."""
    radius, intensity = 1.0, 100.0
    name = f"sphere_{int(rho * 100)}.gltf"
    scene_files.write_gltf(os.path.join(work, name),
                           [{"name": "Sphere", "triangles": scene_files.sphere_inward(radius, 256, 128),
                             "material": 0}],
                           [{"name": "Wall", "pbrMetallicRoughness": {"baseColorFactor": [rho, rho, rho, 1],
                                                                     "metallicFactor": 0}}])
    scene = {"fly": 1, "models": [{"file": os.path.join(work, name)}],
             "lights": [{"name": "bulb", "type": "point", "position": [0, 0, 0], "intensity": intensity}]}
    indirect = rho * intensity / (radius ** 2 * (1 - rho))
    sensors, exact = [], {}
    directions = [(0, 1, 0), (0, -1, 0), (1, 0, 0), (0.6, 0, -0.8), (-0.48, 0.6, 0.64)]
    for k, u in enumerate(directions):
        for d, group in ((0.5, "inner-facing-light"), (0.5, "inner-facing-away"), (radius - 0.01, "wall")):
            p = tuple(d * c for c in u)
            n = tuple(-c for c in u) if group != "inner-facing-away" else u
            sensors.append(p + n + (group,))
            direct = intensity / d ** 2 if group != "inner-facing-away" else 0.0
            exact[len(sensors) - 1] = direct + indirect
    return {"scene": scene, "sensors": sensors, "exact": exact}


def case_alpha_mask(work, filter_mode=9729):
    """A 2 m square leaf (alphaMode MASK, cutoff 0.5, one-sided facing up, albedo 0.7, a texture of 8 × 8
    cells alternately alpha 0.2 and 1, RGB 255: sRGB 1.0; sampled LINEAR, or NEAREST in alpha-mask-nearest)
    1 m above a 20 m floor (albedo 0.5) under a 1000 lx light from 30° off the zenith. Sensors on the floor under the leaf's shadow (cells of either
    kind), facing up; on the leaf's top; under the leaf facing down (its back face: black)."""
    scene_files.write_png_rgba(os.path.join(work, "mask.png"), 64, 64,
                               lambda x, y: (255, 255, 255, 51 if ((x // 8) + (y // 8)) % 2 else 255))
    floor, floor_uv = scene_files.quad((0, 0, 0), 10, 10, (0, 0, 1), (1, 0, 0))
    leaf, leaf_uv = scene_files.quad((0, 1, 0), 1, 1, (0, 0, 1), (1, 0, 0))
    scene_files.write_gltf(
        os.path.join(work, "mask.gltf"),
        [{"name": "Floor", "triangles": floor, "uvs": floor_uv, "material": 0},
         {"name": "Leaf", "triangles": leaf, "uvs": leaf_uv, "material": 1}],
        [{"name": "Floor", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0}},
         {"name": "Leaf", "alphaMode": "MASK", "alphaCutoff": 0.5,
          "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1], "metallicFactor": 0,
                                   "baseColorTexture": {"index": 0}}}],
        images=["mask.png"], filter_mode=filter_mode)
    theta = math.radians(30.0)
    scene = {"fly": 1, "models": [{"file": os.path.join(work, "mask.gltf")}],
             "lights": [{"name": "sun", "type": "directional", "intensity": 1000.0,
                         "direction": [math.sin(theta), -math.cos(theta), 0]}]}
    sensors = []
    shift = math.tan(theta) * 1.0  # the leaf's shadow on the floor moves +x by this
    for i in range(8):
        for j in range(8):
            u, v = (i + 0.5) / 8, (j + 0.5) / 8  # cell centres in texture space
            # quad(): u along +z, v along +x from the corner (−1, −1): world z = 2u − 1, x = 2v − 1.
            x, z = 2 * v - 1, 2 * u - 1
            if (i + j) % 2 == 0 and (i * 8 + j) % 3:
                continue  # every opaque cell's shadow would be too many; keep a third
            kind = "hole" if (i + j) % 2 else "opaque"
            sensors.append((x + shift, 0.002, z, 0, 1, 0, f"floor-under-{kind}"))
            sensors.append((x, 1.002, z, 0, 1, 0, f"leaf-top-{kind}"))
            sensors.append((x, 0.998, z, 0, -1, 0, f"leaf-bottom-{kind}"))
    return {"scene": scene, "sensors": sensors}


def case_mixed_lighting(work):
    """Bevy's MixedLightingExample: the SheenChair (textured fabric, wood, metal, a label) on a 3.1 m floor,
    one 2049 lx directional light in the file. Sensors 2 mm off every surface seen from above (floor in and
    out of the chair's shadow, seat and back) and from the four sides (the chair's sides)."""
    path = model("bevy/MixedLightingExample/MixedLightingExample.gltf")
    scene = {"fly": 1, "models": [{"file": path}]}
    return {"scene": scene, "cast": {"spacing": 0.1, "offset": 0.002, "sideways": True, "box": 1.0}}


def case_cornell_box(work):
    """Bevy's CornellBox.glb (the box in millimetre numbers read as metres, 556 m wide; one emissive
    ceiling panel of 100 cd/m², KHR_materials_emissive_strength, double-sided; every material double-sided).
    Sensors 0.5 m off the surfaces hit by 160 rays from a point in the middle of the box."""
    path = model("bevy/CornellBox/CornellBox.glb")
    scene = {"fly": 1, "models": [{"file": path}]}
    return {"scene": scene, "cast": {"from": [-278, 274, -280], "rays": 160, "offset": 0.5}, "quad": 0.05}


def case_cornell_box_small(work):
    """The same Cornell box scaled by 1/1000 in the scene file (a 0.556 m box, the same illuminance at the
    corresponding sensors): whatever depends on the scene's absolute size (ray offsets) shows as a difference
    from cornell-box."""
    path = model("bevy/CornellBox/CornellBox.glb")
    scene = {"fly": 1, "models": [{"file": path, "scale": 0.001}]}
    return {"scene": scene, "cast": {"from": [-0.278, 0.274, -0.280], "rays": 160, "offset": 0.0005},
            "quad": 5e-5}


def case_flight_helmet(work):
    """The Khronos FlightHelmet (Bevy's copy: textured leather, rubber, wood and metal, lenses of alphaMode
    BLEND, one-sided materials but the hose) standing on a 4 m floor of albedo 0.5, under a 2000 lx light
    from 40° off the zenith. Sensors 1 mm off every surface seen from above and from the four sides."""
    floor, floor_uv = scene_files.quad((0, 0, 0), 2, 2, (0, 0, 1), (1, 0, 0))
    scene_files.write_gltf(os.path.join(work, "floor.gltf"),
                           [{"name": "Floor", "triangles": floor, "uvs": floor_uv, "material": 0}],
                           [{"name": "Floor", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1],
                                                                      "metallicFactor": 0}}])
    theta, phi = math.radians(40.0), math.radians(30.0)
    direction = [math.sin(theta) * math.cos(phi), -math.cos(theta), math.sin(theta) * math.sin(phi)]
    scene = {"fly": 1, "models": [{"file": model("bevy/FlightHelmet/FlightHelmet.gltf")},
                                  {"file": os.path.join(work, "floor.gltf")}],
             "lights": [{"name": "sun", "type": "directional", "intensity": 2000.0, "direction": direction}]}
    return {"scene": scene, "cast": {"spacing": 0.05, "offset": 0.001, "sideways": True, "box": 0.4}}


def sun_of(site, time_local):
    """fly's sun for a site and local time (`fly sun --json`): the unit direction towards it in the scene's
    frame (north along −Z, east along +X: northAngle 0) and its direct normal illuminance (lux)."""
    out = subprocess.run([FLY, "sun", "--lat", str(site["latitude"]), "--lon", str(site["longitude"]), "--time",
                          time_local, "--tz", site["timeZone"], "--json"], capture_output=True, text=True, check=True)
    sun = json.loads(out.stdout)
    az, el = math.radians(sun["azimuth_deg"]), math.radians(sun["apparent_elevation_deg"])
    return ([math.sin(az) * math.cos(el), math.sin(el), -math.cos(az) * math.cos(el)],
            sun["direct_normal_illuminance_lux"])


def case_sun_penumbra(work):
    """fly's sun (a disc of 0.533°, `"sky": {"model": "none", "sun": true}`) in Helsinki at noon on
    midsummer's day over a 20 m floor of albedo 0.5, with a 1 m square plate (albedo 0.5, double-sided) 2 m
    above it. Cycles gets a sun lamp of the same direction, illuminance (fly's direct normal illuminance) and
    angle. Sensors facing up on the floor across the plate's shadow edge (the penumbra is 2 m × 0.0093 = 19 mm
    wide, over 6 cm in 3 mm steps) and in full sun 9 m off, where E = E_n sin(elevation) (the floor's
    sensors see neither the floor nor the black sky; the plate's underside adds < 0.001 %)."""
    site = {"latitude": 60.17, "longitude": 24.94, "timeZone": "Europe/Helsinki"}
    time_local = "2026-06-21T12:00"
    to_sun, dni = sun_of(site, time_local)
    floor, _ = scene_files.quad((0, 0, 0), 10, 10, (0, 0, 1), (1, 0, 0))
    plate, _ = scene_files.quad((0, 2, 0), 0.5, 0.5, (0, 0, 1), (1, 0, 0))
    scene_files.write_gltf(os.path.join(work, "plate.gltf"),
                           [{"name": "Floor", "triangles": floor, "material": 0},
                            {"name": "Plate", "triangles": plate, "material": 1}],
                           [{"name": "Floor", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1],
                                                                      "metallicFactor": 0}},
                            {"name": "Plate", "doubleSided": True,
                             "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0}}])
    scene = {"fly": 1, "models": [{"file": os.path.join(work, "plate.gltf")}],
             "site": site, "time": time_local, "sky": {"model": "none", "sun": True}}
    cycles_scene = {"fly": 1, "models": scene["models"],
                    "lights": [{"name": "sun", "type": "directional", "direction": [-c for c in to_sun],
                                "intensity": dni, "angleDeg": 0.533}]}
    sensors, exact = [], {}
    for edge_z in (-0.25, 0.0, 0.25):
        # The shadow of the plate's edge x = +0.5 (and of x = −0.5) at height 2 m, moved along −to_sun.
        for edge_x, name in ((0.5, "edge+x"), (-0.5, "edge-x")):
            t = 2.0 / to_sun[1]
            cx, cz = edge_x - t * to_sun[0], edge_z - t * to_sun[2]
            for k in range(-10, 11):
                sensors.append((cx + 0.003 * k, 0.001, cz, 0, 1, 0, "penumbra-" + name))
    for x, z in ((9, 9), (-9, 8), (8, -9)):
        sensors.append((x, 0.001, z, 0, 1, 0, "full-sun"))
        exact[len(sensors) - 1] = dni * to_sun[1]
    return {"scene": scene, "cycles_scene": cycles_scene, "sensors": sensors, "exact": exact}


def case_khronos_yard(work):
    """Khronos sample models placed by the scene file on a 12 m floor of albedo 0.5 under a 1500 lx light from
    50° off the zenith: CesiumMilkTruck (4 textured materials, a node hierarchy), the Duck (textured; moved,
    turned 40° about y and scaled 0.8) and TwoSidedPlane (a textured double-sided 2 m square, tilted 30° about
    x, 1 m up). Sensors 2 mm off every surface seen from above (0.35 m lattice within 4 m) and from the four
    sides."""
    floor, floor_uv = scene_files.quad((0, 0, 0), 6, 6, (0, 0, 1), (1, 0, 0))
    scene_files.write_gltf(os.path.join(work, "floor.gltf"),
                           [{"name": "Yard", "triangles": floor, "uvs": floor_uv, "material": 0}],
                           [{"name": "Yard", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1],
                                                                     "metallicFactor": 0}}])
    theta, phi = math.radians(50.0), math.radians(-60.0)
    scene = {"fly": 1,
             "models": [{"file": model("khronos/CesiumMilkTruck/glTF/CesiumMilkTruck.gltf")},
                        {"file": model("khronos/Duck/glTF/Duck.gltf"), "translation": [3.2, -0.08, 2.0],
                         "rotationDeg": [0, 40, 0], "scale": 0.8},
                        {"file": model("khronos/TwoSidedPlane/glTF/TwoSidedPlane.gltf"),
                         "translation": [-3.2, 1.0, -2.0], "rotationDeg": [30, 0, 0]},
                        {"file": os.path.join(work, "floor.gltf")}],
             "lights": [{"name": "sun", "type": "directional", "intensity": 1500.0,
                         "direction": [math.sin(theta) * math.cos(phi), -math.cos(theta),
                                       math.sin(theta) * math.sin(phi)]}]}
    return {"scene": scene, "cast": {"spacing": 0.35, "offset": 0.002, "sideways": True, "box": 4.0}}


CASES = {
    "plane-sun": case_plane_sun,
    "sphere-point-0.5": lambda w: case_sphere_point(w, 0.5),
    "sphere-point-0.9": lambda w: case_sphere_point(w, 0.9),
    "sun-penumbra": case_sun_penumbra,
    "alpha-mask": case_alpha_mask,
    "alpha-mask-nearest": lambda w: case_alpha_mask(w, 9728),
    "mixed-lighting": case_mixed_lighting,
    "cornell-box": case_cornell_box,
    "cornell-box-small": case_cornell_box_small,
    "flight-helmet": case_flight_helmet,
    "khronos-yard": case_khronos_yard,
}


# ---------------------------------------------------------------------------------------------------------

COMPARE_ONLY = False  # --compare-only: reuse the outputs and run times stored by an earlier run


def run(cmd, log):
    """Runs cmd with its output in log; returns its wall-clock seconds, also kept in timings.json beside the
    log for --compare-only."""
    timings_path = os.path.join(os.path.dirname(log), "timings.json")
    timings = {}
    if os.path.exists(timings_path):
        with open(timings_path) as f:
            timings = json.load(f)
    if COMPARE_ONLY:
        if os.path.basename(log) not in timings:
            raise SystemExit(f"validate: --compare-only: no stored run for {log}")
        return timings[os.path.basename(log)]
    # Blender's embedded Python takes its standard library from the first python3 on PATH: the folder of
    # the blender executable goes first, so that Debian's blender finds Debian's Python (and its numpy, which
    # the glTF importer needs) even when this script runs under another Python (pyenv, a virtual env).
    env = dict(os.environ)
    exe = shutil.which(cmd[0])
    if exe:
        env["PATH"] = os.path.dirname(os.path.realpath(exe)) + os.pathsep + env.get("PATH", "")
    start = time.monotonic()
    with open(log, "w") as f:
        f.write("$ " + " ".join(cmd) + "\n")
        f.flush()
        rc = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT, env=env)
    seconds = time.monotonic() - start
    if rc != 0:
        with open(log) as f:
            tail = f.read()[-3000:]
        raise SystemExit(f"validate: command failed (exit {rc}): {' '.join(cmd)}\n{tail}")
    timings[os.path.basename(log)] = seconds
    with open(timings_path, "w") as f:
        json.dump(timings, f, indent=1)
    return seconds


def blender_cmd(args, *script_args):
    return [args.blender, "-b", "--factory-startup", "-noaudio", "--python-exit-code", "1", "-P",
            os.path.join(HERE, "cycles_irradiance.py"), "--"] + [str(a) for a in script_args]


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def rms(values):
    return math.sqrt(sum(v * v for v in values) / len(values)) if values else float("nan")


def group_stats(rows):
    n = len(rows)
    rel = [r["rel_diff"] for r in rows if r["rel_diff"] is not None]
    return {
        "n": n,
        "within": sum(r["within"] for r in rows) / n,
        "mean_rel": sum(rel) / len(rel) if rel else float("nan"),
        "mean_abs_rel": sum(abs(x) for x in rel) / len(rel) if rel else float("nan"),
        "max_abs_rel": max((abs(x) for x in rel), default=float("nan")),
        "mean_z": sum(r["z_score"] for r in rows) / n,
        "rms_z": rms([r["z_score"] for r in rows]),
        "mean_lux": sum(r["cycles"] for r in rows) / n,
    }


def run_case(name, args):
    work = os.path.join(args.out, name)
    os.makedirs(work, exist_ok=True)
    fly_commit = args.commit
    if COMPARE_ONLY and os.path.exists(os.path.join(work, "result.json")):
        with open(os.path.join(work, "result.json")) as f:
            fly_commit = json.load(f).get("fly_commit", fly_commit)
    spec = CASES[name](work)
    scene = spec["scene"]
    scene.setdefault("overrides", []).extend(scene_files.lambertian_overrides(scene, work))
    scene_path = os.path.join(work, "scene.json")
    with open(scene_path, "w") as f:
        json.dump(scene, f, indent=1)
    # Cycles reads the same scene file, or, where fly computes a light (the sun of a site and time), a copy
    # with that light spelt out.
    cycles_scene_path = scene_path
    if "cycles_scene" in spec:
        cycles_scene = spec["cycles_scene"]
        cycles_scene["overrides"] = scene["overrides"]
        cycles_scene_path = os.path.join(work, "cycles-scene.json")
        with open(cycles_scene_path, "w") as f:
            json.dump(cycles_scene, f, indent=1)
    sensors_path = os.path.join(work, "sensors.csv")
    if "sensors" in spec:
        with open(sensors_path, "w") as f:
            f.write("x,y,z,nx,ny,nz,group\n")
            for row in spec["sensors"]:
                f.write(",".join(f"{v:.6g}" if isinstance(v, (int, float)) else v for v in row) + "\n")
    else:
        cast = spec["cast"]
        extra = []
        for key in ("spacing", "offset", "rays", "box"):
            if key in cast:
                extra += ["--" + key, cast[key]]
        if cast.get("sideways"):
            extra.append("--sideways")
        if "from" in cast:
            extra.append("--from=" + ",".join(str(c) for c in cast["from"]))
        run(blender_cmd(args, "sensors", "--scene", scene_path, "--out", sensors_path, *extra),
            os.path.join(work, "sensors.log"))
    sensors = read_csv(sensors_path)

    fly_csv = os.path.join(work, "fly.csv")
    fly_opts = ["--threads", str(args.threads)]
    if args.fly_max_bounces is not None:
        fly_opts += ["--max-bounces", str(args.fly_max_bounces)]
    fly_opts += ["--samples", str(args.fly_samples)] if args.fly_samples else ["--target-error", args.fly_target]
    fly_opts_seed = fly_opts + ["--seed", str(args.seed)]
    fly_s = run([args.fly, "illuminance", scene_path, "--points", sensors_path, "--out", fly_csv] + fly_opts_seed,
                os.path.join(work, "fly.log"))
    fly_start_s = run([args.fly, "illuminance", scene_path, "--points", sensors_path, "--out",
                       os.path.join(work, "fly-1spp.csv"), "--samples", "1", "--threads", str(args.threads)],
                      os.path.join(work, "fly-1spp.log"))
    cycles_csv = os.path.join(work, "cycles.csv")
    info_path = os.path.join(work, "cycles-info.json")
    cycles_s = run(blender_cmd(args, "irradiance", "--scene", cycles_scene_path, "--points", sensors_path, "--out",
                               cycles_csv, "--info", info_path, "--samples", args.cycles_samples, "--pixels",
                               args.cycles_pixels, "--seed", args.seed, "--threads", args.threads,
                               "--quad-size", spec.get("quad", args.quad_size),
                               "--normals", args.cycles_normals,
                               *(["--untextured"] if args.cycles_untextured else [])),
                   os.path.join(work, "cycles.log"))
    with open(info_path) as f:
        info = json.load(f)

    fly_rows, cyc_rows = read_csv(fly_csv), read_csv(cycles_csv)
    seed_check = None
    if args.seed_check:
        # A second run of each with another seed: the differences between independent estimates, in units
        # of their combined reported standard error, have an RMS of 1 where the reported errors are honest.
        fly2 = os.path.join(work, "fly-seed2.csv")
        run([args.fly, "illuminance", scene_path, "--points", sensors_path, "--out", fly2]
            + fly_opts + ["--seed", str(args.seed + 1)], os.path.join(work, "fly-seed2.log"))
        cyc2 = os.path.join(work, "cycles-seed2.csv")
        run(blender_cmd(args, "irradiance", "--scene", cycles_scene_path, "--points", sensors_path, "--out", cyc2,
                        "--samples", args.cycles_samples, "--pixels", args.cycles_pixels, "--seed", args.seed + 1,
                        "--threads", args.threads, "--quad-size", spec.get("quad", args.quad_size),
                        "--normals", args.cycles_normals,
                        *(["--untextured"] if args.cycles_untextured else [])),
            os.path.join(work, "cycles-seed2.log"))
        seed_check = {}
        for tool, a_rows, b_rows in (("fly", fly_rows, read_csv(fly2)), ("cycles", cyc_rows, read_csv(cyc2))):
            zs = []
            for a, b in zip(a_rows, b_rows):
                d = float(a["illuminance_lux"]) - float(b["illuminance_lux"])
                se = math.hypot(float(a["std_error_lux"]), float(b["std_error_lux"]))
                if se > 0:
                    zs.append(d / se)
            seed_check[tool] = {"n": len(zs), "rms_z": rms(zs),
                                "within_3": sum(abs(z) <= 3 for z in zs) / len(zs) if zs else float("nan")}
    exact = spec.get("exact", {})
    rows = []
    for i, (s, fr, cr) in enumerate(zip(sensors, fly_rows, cyc_rows)):
        f_lux, f_se = float(fr["illuminance_lux"]), float(fr["std_error_lux"])
        c_lux, c_se = float(cr["illuminance_lux"]), float(cr["std_error_lux"])
        # A floor for σ of 0.01 %: where only a delta light reaches a sensor both estimates are exact (σ = 0)
        # up to the precision of the inputs (the sensor file has 6 significant digits).
        sigma = max(math.hypot(f_se, c_se), 1e-4 * abs(c_lux))
        diff = f_lux - c_lux
        row = {k: s[k] for k in ("x", "y", "z", "nx", "ny", "nz", "group")}
        row.update(fly=f_lux, fly_se=f_se, cycles=c_lux, cycles_se=c_se,
                   rel_diff=diff / c_lux if c_lux > 0 else None,
                   z_score=diff / sigma if sigma > 0 else 0.0,
                   within=abs(diff) <= TOLERANCE_SIGMAS * sigma + TOLERANCE_RELATIVE * abs(c_lux))
        if i in exact:
            e = exact[i]
            row.update(exact=e, fly_vs_exact=(f_lux - e) / e, cycles_vs_exact=(c_lux - e) / e,
                       fly_z_exact=(f_lux - e) / max(f_se, 1e-6 * e),
                       cycles_z_exact=(c_lux - e) / max(c_se, 1e-6 * e))
        rows.append(row)
    with open(os.path.join(work, "compare.csv"), "w", newline="") as f:
        keys = list(rows[0].keys())
        for r in rows:
            keys += [k for k in r if k not in keys]
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})

    groups = {}
    for r in rows:
        groups.setdefault(r["group"], []).append(r)
    table = [("all", group_stats(rows))] + [(g, group_stats(rs)) for g, rs in sorted(groups.items())]
    fly_rel = [r["fly_se"] / r["fly"] for r in rows if r["fly"] > 0]
    cyc_rel = [r["cycles_se"] / r["cycles"] for r in rows if r["cycles"] > 0]
    cyc_setup = cycles_s - info["bake_s"]
    timing = {
        "fly_s": fly_s, "fly_start_s": fly_start_s, "fly_rms_rel": rms(fly_rel),
        "cycles_s": cycles_s, "cycles_bake_s": info["bake_s"], "cycles_rms_rel": rms(cyc_rel),
        # RMS relative error ∝ 1/√(samples): time to 1 % = start-up + tracing time × (rms / 1 %)².
        "fly_to_1pct_s": fly_start_s + max(fly_s - fly_start_s, 0) * (rms(fly_rel) / 0.01) ** 2,
        "cycles_to_1pct_s": cyc_setup + info["bake_s"] * (rms(cyc_rel) / 0.01) ** 2,
    }
    exact_rows = [r for r in rows if "exact" in r]
    result = {"case": name, "sensors": len(rows), "groups": table, "timing": timing,
              "cycles_samples_per_sensor": info["samples"] * info["pixels"], "materials": info["materials"],
              "fly_args": fly_opts_seed, "cycles_normals": args.cycles_normals, "cycles_untextured": args.cycles_untextured, "fly_commit": fly_commit}
    if seed_check:
        result["seed_check"] = seed_check
    if exact_rows:
        result["exact"] = {
            "fly_max_abs_rel": max(abs(r["fly_vs_exact"]) for r in exact_rows),
            "fly_mean_rel": sum(r["fly_vs_exact"] for r in exact_rows) / len(exact_rows),
            "fly_max_abs_z": max(abs(r["fly_z_exact"]) for r in exact_rows),
            "cycles_max_abs_rel": max(abs(r["cycles_vs_exact"]) for r in exact_rows),
            "cycles_mean_rel": sum(r["cycles_vs_exact"] for r in exact_rows) / len(exact_rows),
            "cycles_max_abs_z": max(abs(r["cycles_z_exact"]) for r in exact_rows),
        }
    with open(os.path.join(work, "result.json"), "w") as f:
        json.dump(result, f, indent=1)
    print(format_case(result))
    return result


def format_case(res):
    t = res["timing"]
    lines = [f"### {res['case']}", "", f"fly at {res.get('fly_commit', '?')}; fly {' '.join(res.get('fly_args', []))}"
             f"{'; Cycles without textures, vertex colours and alpha' if res.get('cycles_untextured') else ''}", "",
             f"{res['sensors']} sensors; fly {t['fly_s']:.1f} s (start-up {t['fly_start_s']:.1f} s, RMS relative "
             f"error {100 * t['fly_rms_rel']:.2f} %, to 1 %: {t['fly_to_1pct_s']:.1f} s); Cycles {t['cycles_s']:.1f} s "
             f"(bake {t['cycles_bake_s']:.1f} s, {res['cycles_samples_per_sensor']} samples per sensor, RMS "
             f"relative error {100 * t['cycles_rms_rel']:.2f} %, to 1 %: {t['cycles_to_1pct_s']:.1f} s)", "",
             "| group | sensors | mean E (lx, Cycles) | within 3σ + 2 % | mean rel. diff | mean abs. rel. diff "
             "| max abs. rel. diff | RMS of z |",
             "|---|---|---|---|---|---|---|---|"]
    for g, s in res["groups"]:
        lines.append(f"| {g} | {s['n']} | {s['mean_lux']:.4g} | {100 * s['within']:.1f} % | "
                     f"{100 * s['mean_rel']:+.2f} % | {100 * s['mean_abs_rel']:.2f} % | "
                     f"{100 * s['max_abs_rel']:.2f} % | {s['rms_z']:.2f} |")
    if "seed_check" in res:
        f, c = res["seed_check"]["fly"], res["seed_check"]["cycles"]
        lines += ["", f"Two seeds: fly's differences / their σ have RMS {f['rms_z']:.2f} ({100 * f['within_3']:.1f} % "
                  f"within 3, {f['n']} sensors with σ > 0); Cycles' RMS {c['rms_z']:.2f} ({100 * c['within_3']:.1f} % "
                  f"within 3, {c['n']} sensors)"]
    if "exact" in res:
        e = res["exact"]
        lines += ["", f"Against the exact values: fly mean {100 * e['fly_mean_rel']:+.3f} %, max "
                  f"|{100 * e['fly_max_abs_rel']:.3f}| %, max |z| {e['fly_max_abs_z']:.2f}; Cycles mean "
                  f"{100 * e['cycles_mean_rel']:+.3f} %, max |{100 * e['cycles_max_abs_rel']:.3f}| %, "
                  f"max |z| {e['cycles_max_abs_z']:.2f}"]
    return "\n".join(lines) + "\n"


def format_overview(results):
    lines = ["| case | fly | sensors | within 3σ + 2 % | mean rel. diff | mean abs. rel. diff | max abs. rel. diff "
             "| RMS of z | fly s (to 1 %) | Cycles s (to 1 %) |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        a, t = r["groups"][0][1], r["timing"]
        lines.append(f"| {r['case']}{' (Cycles untextured)' if r.get('cycles_untextured') else ''} | "
                     f"{r.get('fly_commit', '?').split()[0]} | {a['n']} | {100 * a['within']:.1f} % | {100 * a['mean_rel']:+.2f} % | "
                     f"{100 * a['mean_abs_rel']:.2f} % | {100 * a['max_abs_rel']:.1f} % | {a['rms_z']:.2f} | "
                     f"{t['fly_s']:.1f} ({t['fly_to_1pct_s']:.1f}) | {t['cycles_s']:.1f} ({t['cycles_to_1pct_s']:.1f}) |")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("cases", nargs="*", help="cases to run (default: all)")
    ap.add_argument("--list", action="store_true", help="print the cases and exit")
    ap.add_argument("--compare-only", action="store_true",
                    help="recompute the comparisons from the outputs of an earlier run in DIR (same options)")
    ap.add_argument("--summary-only", action="store_true",
                    help="rewrite DIR/summary.md from the cases' stored result.json without running anything")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "validation"))
    ap.add_argument("--fly", default=os.path.join(ROOT, "build", "cli", "fly"))
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--fly-target", default="1%", help="fly's --target-error (default 1%%)")
    ap.add_argument("--fly-samples", type=int, default=0, help="fly's --samples instead of a target error")
    ap.add_argument("--fly-max-bounces", type=int, help="fly's --max-bounces (default: fly's default)")
    ap.add_argument("--cycles-samples", type=int, default=256, help="Cycles samples per texel")
    ap.add_argument("--cycles-pixels", type=int, default=4, help="texels per side of a sensor's block")
    ap.add_argument("--cycles-untextured", action="store_true",
                    help="Cycles ignores textures, vertex colours and alpha (to check the rest of the set-up "
                         "against a fly that does not read them)")
    ap.add_argument("--cycles-normals", choices=("shading", "geometric"), default="shading",
                    help="Cycles shades with the files' vertex normals (as fly's baker does since 8825540) or "
                         "with geometric normals (as it did before)")
    ap.add_argument("--quad-size", type=float, default=1e-4,
                    help="Cycles sensor square's side, metres (cases of other scales set their own)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--seed-check", action="store_true",
                    help="run both again with seed + 1 and check their reported errors against the difference")
    ap.add_argument("--threads", type=int, default=0, help="threads for both (0: all cores)")
    args = ap.parse_args()
    if args.list:
        for name, fn in CASES.items():
            doc = (fn.__doc__ or "").strip() if not name.startswith("sphere") else case_sphere_point.__doc__
            doc = " ".join(doc.split())
            print(f"{name}: {doc.split('. ')[0].rstrip('.')}.")
        return
    names = args.cases or list(CASES)
    for n in names:
        if n not in CASES:
            raise SystemExit(f"validate: unknown case '{n}'; cases: {', '.join(CASES)}")
    global FLY
    FLY = args.fly = os.path.abspath(args.fly)
    if not os.path.exists(args.fly):
        raise SystemExit(f"validate: {args.fly} not found; build fly first (./scripts/build)")
    args.out = os.path.abspath(args.out)
    os.makedirs(args.out, exist_ok=True)
    # The fly that ran: the last commit that changed its sources.
    sources = ["base", "sdb", "rdb", "raytracer", "sunsky", "cli", "cmake", "CMakeLists.txt"]
    commit = subprocess.run(["git", "-C", ROOT, "log", "-1", "--format=%h %cs %s", "--"] + sources,
                            capture_output=True, text=True).stdout.strip()
    dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no", "--"] + sources,
                           capture_output=True, text=True).stdout.strip()
    commit += " (with uncommitted changes)" if dirty else ""
    args.commit = commit
    global COMPARE_ONLY
    COMPARE_ONLY = args.compare_only
    if args.summary_only:
        results = []
        for n in names:
            path = os.path.join(args.out, n, "result.json")
            if os.path.exists(path):
                with open(path) as f:
                    results.append(json.load(f))
    else:
        results = [run_case(n, args) for n in names]
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        f.write(f"Summary written with the harness at {commit}\n\nCycles {args.cycles_samples} samples × {args.cycles_pixels}² texels; "
                f"fly {'--samples ' + str(args.fly_samples) if args.fly_samples else '--target-error ' + args.fly_target}"
                f"{'' if args.fly_max_bounces is None else ' --max-bounces ' + str(args.fly_max_bounces)}\n\n")
        f.write(format_overview(results) + "\n")
        for r in results:
            f.write(format_case(r) + "\n")


if __name__ == "__main__":
    main()
