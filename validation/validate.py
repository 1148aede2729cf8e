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


# The Cornell box's light faces down only (Cornell's data: a panel under the ceiling's opening). Bevy's
# CornellBox.glb makes it double-sided, emitting from its back face too into the 0.887 m gap between the panel
# (y = 547.9) and the ceiling (548.8): a bright slot (the back face 100 cd/m², the ceiling above it lit by
# it) whose light leaks out through the 0.9 m slit around the panel's edge. That light is real (+1.1 % on
# average over the sensors, up to 5 % high on the walls) but reaches a sensor only along the rare paths that
# enter the slit, with weights hundreds of times a sensor's illuminance: both programs' estimates are then
# heavy-tailed and their reported errors unreliable (docs/validation.md, "Speed to 1 %, measured").
# cornell-box-two-sided-light keeps the file's double-sided panel.
ONE_SIDED_CORNELL_LIGHT = [{"material": "Emitter_Light_temp", "doubleSided": False}]


def case_cornell_box(work, two_sided_light=False, scale=1.0):
    """Bevy's CornellBox.glb (the box in millimetre numbers read as metres, 556 m wide; one emissive ceiling
    panel of 100 cd/m², KHR_materials_emissive_strength; every material double-sided), the panel one-sided
    facing down as in Cornell's box (two_sided_light: as the file has it); scale 0.001 in
    cornell-box-small. Sensors 0.5 m (× scale) off the surfaces hit by 160 rays from a point in the middle
    of the box."""
    path = model("bevy/CornellBox/CornellBox.glb")
    scene = {"fly": 1, "models": [{"file": path, **({"scale": scale} if scale != 1.0 else {})}]}
    if not two_sided_light:
        scene["overrides"] = [dict(o) for o in ONE_SIDED_CORNELL_LIGHT]
    return {"scene": scene, "cast": {"from": [-278 * scale, 274 * scale, -280 * scale], "rays": 160,
                                     "offset": 0.5 * scale}, "quad": 0.05 * scale}


def case_cornell_box_small(work):
    """The same Cornell box scaled by 1/1000 in the scene file (a 0.556 m box, the same illuminance at the
    corresponding sensors): whatever depends on the scene's absolute size (ray offsets) shows as a difference
    from cornell-box."""
    return case_cornell_box(work, scale=0.001)


def case_cornell_box_two_sided_light(work):
    """Bevy's CornellBox.glb as the file has it: the ceiling panel emits from both faces, its back face into
    the gap under the ceiling (ONE_SIDED_CORNELL_LIGHT says why the other cases turn it one-sided)."""
    return case_cornell_box(work, two_sided_light=True)


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


def fly_sky_diffuse_lux(scene_path):
    """The diffuse horizontal illuminance of the scene's sky as fly computes it (`fly info --json`: the light's
    description, "… (sun S, sky D)" in lux)."""
    out = subprocess.run([FLY, "info", scene_path, "--json"], capture_output=True, text=True, check=True)
    text = json.loads(out.stdout)["light"]["description"]
    marker = "sky "
    at = text.rfind(marker)
    if at < 0 or not text.endswith(")"):
        raise SystemExit(f"validate: cannot read the sky's illuminance from fly info: {text}")
    return float(text[at + len(marker):-1])


def case_sunlit_room(work):
    """A closed room 8 × 3 × 6 m (floor albedo 0.4, walls 0.6, ceiling 0.8, one-sided facing in) with a 3 × 1.5 m
    window opening (sill 0.8 m) in its south wall, on a 100 m ground of albedo 0.3 outside, in Helsinki on 15
    April at 13:00 under fly's sun (0.533° disc, 79.6 klx direct normal, 39.5° up, azimuth 173.5°) and a CIE
    sky of type 5 (uniform luminance, at fly's default level of 13.7 klx diffuse horizontal): the sun falls
    through the opening onto the floor, and the room is lit mostly by light reflected from that patch. Cycles
    gets a sun lamp of the same direction, illuminance and angle and a world of the sky's uniform radiance
    above the horizon, black below (as fly's sky). Sensors 2 mm off the floor in and out of the sun patch
    (none within 5 cm of its edges, which the sun's disc blurs by 2 cm), on a work plane 0.85 m up, on the
    four walls and the ceiling, and one on the open ground 49 m from the room, where E ≈ E_n sin(elevation) +
    the sky's diffuse horizontal illuminance (the room hides a few 0.01 % of the sky: not exact, so the
    driver prints both programs' difference from it rather than testing it). Both programs get the opening as
    a sky portal."""
    site = {"latitude": 60.17, "longitude": 24.94, "timeZone": "Europe/Helsinki"}
    time_local = "2026-04-15T13:00"
    to_sun, dni = sun_of(site, time_local)
    win_x, win_y = (-1.5, 1.5), (0.8, 2.3)

    def rect(x0, y0, z0, ex, ey):
        """Two triangles of the rectangle corner + s·ex + t·ey, s, t ∈ [0, 1], front face along ex × ey."""
        a = (x0, y0, z0)
        b = tuple(a[i] + ex[i] for i in range(3))
        c = tuple(a[i] + ex[i] + ey[i] for i in range(3))
        d = tuple(a[i] + ey[i] for i in range(3))
        return [(a, b, c), (a, c, d)]

    floor = rect(-4, 0, -3, (0, 0, 6), (8, 0, 0))              # +Y
    ceiling = rect(-4, 3, -3, (8, 0, 0), (0, 0, 6))            # −Y
    walls = (rect(-4, 0, -3, (0, 3, 0), (0, 0, 6))             # x = −4, +X
             + rect(4, 0, -3, (0, 0, 6), (0, 3, 0))            # x = 4, −X
             + rect(-4, 0, -3, (8, 0, 0), (0, 3, 0))           # z = −3 (north), +Z
             # z = 3 (south), facing −Z, around the opening
             + rect(-4, 0, 3, (0, 3, 0), (2.5, 0, 0)) + rect(1.5, 0, 3, (0, 3, 0), (2.5, 0, 0))
             + rect(-1.5, 0, 3, (0, 0.8, 0), (3, 0, 0)) + rect(-1.5, 2.3, 3, (0, 0.7, 0), (3, 0, 0)))
    ground = rect(-50, -0.05, -50, (0, 0, 100), (100, 0, 0))   # +Y
    scene_files.write_gltf(
        os.path.join(work, "room.gltf"),
        [{"name": "Floor", "triangles": floor, "material": 0}, {"name": "Ceiling", "triangles": ceiling, "material": 1},
         {"name": "Walls", "triangles": walls, "material": 2}, {"name": "Ground", "triangles": ground, "material": 3}],
        [{"name": name, "pbrMetallicRoughness": {"baseColorFactor": [rho, rho, rho, 1], "metallicFactor": 0}}
         for name, rho in (("Floor", 0.4), ("Ceiling", 0.8), ("Wall", 0.6), ("Ground", 0.3))])
    # The opening as a sky portal for both programs (docs/scene-format.md, portals; Cycles: a portal light).
    portals = [{"name": "opening", "corners": [[win_x[0], win_y[0], 3], [win_x[1], win_y[0], 3],
                                               [win_x[1], win_y[1], 3], [win_x[0], win_y[1], 3]]}]
    scene = {"fly": 1, "models": [{"file": os.path.join(work, "room.gltf")}], "site": site, "time": time_local,
             "sky": {"model": "cie", "cieType": 5, "sun": True}, "portals": portals}
    probe = os.path.join(work, "sky-probe.json")
    with open(probe, "w") as f:
        json.dump(scene, f)
    sky_lux = fly_sky_diffuse_lux(probe)
    cycles_scene = {"fly": 1, "models": scene["models"],
                    "lights": [{"name": "sun", "type": "directional", "direction": [-c for c in to_sun],
                                "intensity": dni, "angleDeg": 0.533}],
                    "world": {"skyRadianceCdM2": sky_lux / math.pi}, "portals": portals}

    def sunlit(p):
        """Does the ray from p towards the sun pass through the opening, at least 5 cm inside its edges?"""
        if to_sun[2] <= 0:
            return False, 0.0
        t = (3 - p[2]) / to_sun[2]
        x, y = p[0] + t * to_sun[0], p[1] + t * to_sun[1]
        margin = min(x - win_x[0], win_x[1] - x, y - win_y[0], win_y[1] - y)
        return margin > 0, abs(margin)

    sensors = []
    for x in (-3.5, -2.5, -1.5, -0.5, 0.5, 1.5, 2.5, 3.5):
        for z in (-2.5, -1.5, -0.5, 0.5, 1.5, 2.5):
            for y, name in ((0.002, "floor"), (0.85, "workplane")):
                lit, margin = sunlit((x, y, z))
                if margin < 0.05:
                    continue
                if name == "workplane" and (x + z) % 2:
                    continue  # half the work-plane lattice
                sensors.append((x, y, z, 0, 1, 0, f"{name}-{'sun' if lit else 'shade'}"))
    for z in (-2, 0, 2):
        for y in (1.0, 2.2):
            sensors.append((-3.998, y, z, 1, 0, 0, "wall-west"))
            sensors.append((3.998, y, z, -1, 0, 0, "wall-east"))
    for x in (-3, -1, 1, 3):
        for y in (1.0, 2.2):
            sensors.append((x, y, -2.998, 0, 0, 1, "wall-north"))
    for x in (-3, 3):
        for y in (1.0, 2.2):
            sensors.append((x, y, 2.998, 0, 0, -1, "wall-south"))
    for x in (-3, -1, 1, 3):
        for z in (-2, 0, 2):
            sensors.append((x, 2.998, z, 0, -1, 0, "ceiling"))
    sensors.append((35.0, -0.048, -35.0, 0, 1, 0, "outside"))
    return {"scene": scene, "cycles_scene": cycles_scene, "sensors": sensors,
            "formula": {len(sensors) - 1: dni * to_sun[1] + sky_lux}}


CASES = {
    "plane-sun": case_plane_sun,
    "sphere-point-0.5": lambda w: case_sphere_point(w, 0.5),
    "sphere-point-0.9": lambda w: case_sphere_point(w, 0.9),
    "sun-penumbra": case_sun_penumbra,
    "sunlit-room": case_sunlit_room,
    "alpha-mask": case_alpha_mask,
    "alpha-mask-nearest": lambda w: case_alpha_mask(w, 9728),
    "mixed-lighting": case_mixed_lighting,
    "cornell-box": case_cornell_box,
    "cornell-box-small": case_cornell_box_small,
    "cornell-box-two-sided-light": case_cornell_box_two_sided_light,
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


def rms_relative_error(csv_path):
    """RMS over the sensors of the reported standard error relative to the estimate."""
    rows = read_csv(csv_path)
    return rms([float(r["std_error_lux"]) / float(r["illuminance_lux"]) for r in rows
                if float(r["illuminance_lux"]) > 0])


def time_line(runs):
    """Least-squares line a + b · samples through the runs' wall-clock times (the mean time of each sample
    count): a is the start-up and everything else that does not grow with the samples, b the time a sample
    (a run of one sample count gives its time and no slope)."""
    by = {}
    for r in runs:
        by.setdefault(r["samples"], []).append(r["s"])
    xs = sorted(by)
    ys = [sum(by[x]) / len(by[x]) for x in xs]
    if len(xs) < 2:
        return ys[0], 0.0  # one sample count: no slope to tell, its time stands
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    return my - b * mx, b


def speed_runs(work, args, fly_run, cycles_run, fly_start_s):
    """--speed: runs each program until the RMS relative standard error over the sensors reaches
    args.speed_target, start-up included, alternating between the two so that both meet the same load. fly
    takes samples per sensor in powers of two (its --samples), from a pilot of args.speed_fly_pilot, each next
    count half the least power of two that the last run's RMS predicts to reach the target (RMS ∝
    1/√samples; fly's quasi-Monte Carlo converges faster), at least twice the last. Cycles takes samples per texel from a pilot of args.speed_cycles_pilot, each next
    count the prediction + 15 %. The first configuration of each that reaches the target is then run again
    until each has args.repeats runs of it (same seed, so the same answer; only the time differs), still
    alternating. Measured: the mean wall-clock time of those runs. Fitted: the time at exactly the target, on
    the line through each program's wall-clock times against its samples (time_line: start-up and other fixed
    costs plus a time per sample), at the samples that the last run's RMS predicts for the target (RMS ∝
    1/√samples); it removes fly's overshoot from its power-of-two steps. Cycles gets a second point of its line
    at 8 × its pilot's samples; with --cycles-budget-s, a run the line predicts to take longer is replaced by
    one within the budget, and Cycles' time is then fitted only."""
    target = args.speed_target
    fly = {"runs": []}
    cyc = {"runs": []}

    def fly_step(samples, rep=0):
        csv_path = os.path.join(work, f"fly-speed-{samples}.csv")
        t = fly_run(csv_path, f"fly-speed-{samples}-{rep}.log", ["--samples", str(samples)])
        fly["runs"].append({"samples": samples, "s": t, "rms": rms_relative_error(csv_path), "csv": csv_path})

    def cycles_step(samples, rep=0):
        csv_path = os.path.join(work, f"cycles-speed-{samples}.csv")
        info_path = os.path.join(work, f"cycles-speed-{samples}-{rep}-info.json")
        t = cycles_run(csv_path, f"cycles-speed-{samples}-{rep}.log", samples, info_path)
        with open(info_path) as f:
            bake_s = json.load(f)["bake_s"]
        cyc["runs"].append({"samples": samples, "s": t, "bake_s": bake_s, "rms": rms_relative_error(csv_path),
                            "csv": csv_path, "info": info_path})

    def fly_next(last):
        # The least power of two that RMS ∝ 1/√samples predicts, then one below it first: Owen-scrambled
        # Sobol' points converge faster than that (the prediction from the pilot overshot 4 096 samples where
        # 2 048 sufficed on the Cornell box), and the next step doubles if it falls short.
        need = last["samples"] * (last["rms"] / target) ** 2
        n = 1
        while n < need:
            n *= 2
        return max(n // 2, 2 * last["samples"])

    def cycles_next(last):
        return max(int(math.ceil(1.15 * last["samples"] * (last["rms"] / target) ** 2)), last["samples"] + 1)

    fly_step(args.speed_fly_pilot)
    cycles_step(args.speed_cycles_pilot)
    # A second point of Cycles' curve at 8 times the pilot's samples, for the line through its times.
    if cyc["runs"][-1]["rms"] > target:
        cycles_step(min(8 * args.speed_cycles_pilot, cycles_next(cyc["runs"][-1])))
    cycles_done = False  # reached the target, or stopped at --cycles-budget-s (then fitted only)
    while fly["runs"][-1]["rms"] > target or not cycles_done:
        if fly["runs"][-1]["rms"] > target:
            if fly["runs"][-1]["samples"] >= 1 << 20:
                raise SystemExit("validate: --speed: fly did not reach the target within 2^20 samples")
            fly_step(fly_next(fly["runs"][-1]))
        last = cyc["runs"][-1]
        if last["rms"] <= target:
            cycles_done = True
        elif not cycles_done:
            samples = cycles_next(last)
            a, b = time_line(cyc["runs"])
            if args.cycles_budget_s and a + b * samples > args.cycles_budget_s:
                # A run to the target would take too long: one more point of the curve within the budget, and
                # the time to the target fitted from it.
                samples = int((args.cycles_budget_s - a) / b) if b > 0 else last["samples"]
                cycles_done = True
                cyc["fitted_only"] = True
                if samples <= last["samples"]:
                    continue
            cycles_step(samples)
    fly_final, cyc_final = fly["runs"][-1], cyc["runs"][-1]
    for rep in range(1, args.repeats):
        fly_step(fly_final["samples"], rep)
        if not cyc.get("fitted_only"):
            cycles_step(cyc_final["samples"], rep)
    for prog, final in ((fly, fly_final), (cyc, cyc_final)):
        times = [r["s"] for r in prog["runs"] if r["samples"] == final["samples"]]
        prog.update(final_samples=final["samples"], final_rms=final["rms"], measured_s=sum(times) / len(times),
                    measured_runs=times)
    fly["start_s"] = fly_start_s
    finals = [r for r in cyc["runs"] if r["samples"] == cyc_final["samples"]]
    cyc["start_s"] = sum(r["s"] - r["bake_s"] for r in finals) / len(finals)  # Cycles' time outside its bake
    for prog, final in ((fly, fly_final), (cyc, cyc_final)):
        a, b = time_line(prog["runs"])
        prog["samples_at_target"] = final["samples"] * (final["rms"] / target) ** 2
        prog["time_line"] = [a, b]
        prog["fitted_s"] = a + b * prog["samples_at_target"]
    speed = {"target": target, "fly": fly, "cycles": cyc,
             "ratio_measured": None if cyc.get("fitted_only") else cyc["measured_s"] / fly["measured_s"],
             "ratio_fitted": cyc["fitted_s"] / fly["fitted_s"], "threads": args.threads,
             "load_before": os.getloadavg()}
    return (speed, fly_final["csv"], cyc_final["csv"], cyc_final["info"], fly["measured_s"], cyc["measured_s"])


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

    fly_opts = ["--threads", str(args.threads)]
    if args.fly_max_bounces is not None:
        fly_opts += ["--max-bounces", str(args.fly_max_bounces)]
    if not args.speed:
        fly_opts += ["--samples", str(args.fly_samples)] if args.fly_samples else ["--target-error", args.fly_target]
    cycles_opts = ["--pixels", args.cycles_pixels, "--threads", args.threads,
                   "--quad-size", spec.get("quad", args.quad_size), "--normals", args.cycles_normals,
                   *(["--untextured"] if args.cycles_untextured else [])]

    def fly_run(csv_path, log_name, extra, seed=args.seed):
        return run([args.fly, "illuminance", scene_path, "--points", sensors_path, "--out", csv_path] + fly_opts
                   + extra + ["--seed", str(seed)], os.path.join(work, log_name))

    def cycles_run(csv_path, log_name, samples, info_path=None, seed=args.seed):
        return run(blender_cmd(args, "irradiance", "--scene", cycles_scene_path, "--points", sensors_path, "--out",
                               csv_path, *(["--info", info_path] if info_path else []), "--samples", samples,
                               "--seed", seed, *cycles_opts), os.path.join(work, log_name))

    fly_start_s = run([args.fly, "illuminance", scene_path, "--points", sensors_path, "--out",
                       os.path.join(work, "fly-1spp.csv"), "--samples", "1", "--threads", str(args.threads)],
                      os.path.join(work, "fly-1spp.log"))
    speed = None
    if args.speed:
        speed, fly_csv, cycles_csv, info_path, fly_s, cycles_s = speed_runs(work, args, fly_run, cycles_run,
                                                                            fly_start_s)
        fly_opts_seed = fly_opts + ["--samples", str(speed["fly"]["final_samples"]), "--seed", str(args.seed)]
    else:
        fly_csv = os.path.join(work, "fly.csv")
        fly_opts_seed = fly_opts + ["--seed", str(args.seed)]
        fly_s = fly_run(fly_csv, "fly.log", [])
        cycles_csv = os.path.join(work, "cycles.csv")
        info_path = os.path.join(work, "cycles-info.json")
        cycles_s = cycles_run(cycles_csv, "cycles.log", args.cycles_samples, info_path)
    with open(info_path) as f:
        info = json.load(f)

    fly_rows, cyc_rows = read_csv(fly_csv), read_csv(cycles_csv)
    seed_check = None
    if args.seed_check:
        # A second run of each with another seed: the differences between independent estimates, in units
        # of their combined reported standard error, have an RMS of 1 where the reported errors are honest.
        fly2 = os.path.join(work, "fly-seed2.csv")
        fly_run(fly2, "fly-seed2.log", fly_opts_seed[len(fly_opts):-2], seed=args.seed + 1)
        cyc2 = os.path.join(work, "cycles-seed2.csv")
        cycles_run(cyc2, "cycles-seed2.log", info["samples"], seed=args.seed + 1)
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
    for i, value in spec.get("formula", {}).items():
        print(f"{name}: sensor {i} ({sensors[i]['group']}): formula {value:.6g} lx; fly "
              f"{100 * (float(fly_rows[i]['illuminance_lux']) / value - 1):+.4f} %, Cycles "
              f"{100 * (float(cyc_rows[i]['illuminance_lux']) / value - 1):+.4f} %")
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
    if speed:
        result["speed"] = speed
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
    if "speed" in res:
        sp = res["speed"]
        f, c = sp["fly"], sp["cycles"]
        lines += ["", f"Speed to an RMS relative error of {100 * sp['target']:g} % ({sp['threads']} threads each, "
                  f"alternating): fly {f['measured_s']:.2f} s at {f['final_samples']} samples (RMS "
                  f"{100 * f['final_rms']:.2f} %; start-up (1 sample) {f['start_s']:.2f} s; fitted to the target "
                  f"{f['fitted_s']:.2f} s); Cycles {c['measured_s']:.2f} s at {c['final_samples']} samples × "
                  f"{res['cycles_samples_per_sensor'] // c['final_samples']} texels (RMS {100 * c['final_rms']:.2f} %; "
                  f"outside the bake {c['start_s']:.2f} s; fitted {c['fitted_s']:.2f} s); Cycles / fly "
                  f"{'—' if sp['ratio_measured'] is None else format(sp['ratio_measured'], '.1f')} measured, "
                  f"{sp['ratio_fitted']:.1f} fitted"
                  f"{' (Cycles stopped short of the target at --cycles-budget-s: its time is fitted)' if c.get('fitted_only') else ''}",
                  "", "| program | samples | wall s | RMS rel. error |", "|---|---|---|---|"]
        for prog, p in (("fly", f), ("Cycles", c)):
            for r in p["runs"]:
                lines.append(f"| {prog} | {r['samples']} | {r['s']:.2f} | {100 * r['rms']:.2f} % |")
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


def format_speed(results):
    rows = [r for r in results if "speed" in r]
    if not rows:
        return ""
    lines = ["| case | sensors | fly samples | fly s (fitted) | Cycles samples per sensor | Cycles s (fitted) "
             "| Cycles / fly measured | fitted |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        sp = r["speed"]
        f, c = sp["fly"], sp["cycles"]
        lines.append(f"| {r['case']} | {r['sensors']} | {f['final_samples']} | {f['measured_s']:.2f} ({f['fitted_s']:.2f}) "
                     f"| {r['cycles_samples_per_sensor']} | "
                     f"{'—' if c.get('fitted_only') else format(c['measured_s'], '.2f')} ({c['fitted_s']:.2f}) | "
                     f"{'—' if sp['ratio_measured'] is None else format(sp['ratio_measured'], '.1f')} | "
                     f"{sp['ratio_fitted']:.1f} |")
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
    ap.add_argument("--speed", action="store_true",
                    help="run each program until the RMS relative error over the sensors reaches --speed-target, "
                         "alternating, and compare their times (the comparison uses those runs' outputs)")
    ap.add_argument("--speed-target", type=float, default=0.01, help="RMS relative error for --speed (default 0.01)")
    ap.add_argument("--speed-fly-pilot", type=int, default=256, help="fly's first samples per sensor in --speed")
    ap.add_argument("--speed-cycles-pilot", type=int, default=16, help="Cycles' first samples per texel in --speed")
    ap.add_argument("--repeats", type=int, default=2, help="--speed: runs of each program's final configuration")
    ap.add_argument("--cycles-budget-s", type=float, default=0.0,
                    help="--speed: a Cycles bake predicted to take longer than this to reach the target is run "
                         "within it instead, and Cycles' time to the target is fitted (0: no limit)")
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
        if any("speed" in r for r in results):
            f.write(f"Time to an RMS relative error of {100 * args.speed_target:g} %, start-up included "
                    f"(--speed):\n\n" + format_speed(results) + "\n")
        for r in results:
            f.write(format_case(r) + "\n")


if __name__ == "__main__":
    main()
