# Irradiance (lux) at sensor points computed by Blender Cycles, as an independent reference for
# `fly illuminance`. Run inside Blender (the Debian package `blender`, 3.4, whose glTF importer
# io_scene_gltf2 is enabled under --factory-startup):
#
#   blender -b --factory-startup -P validation/cycles_irradiance.py -- irradiance \
#       --scene SCENE.json --points SENSORS.csv --out OUT.csv [--samples 256] [--pixels 4] [--seed 0]
#   blender -b --factory-startup -P validation/cycles_irradiance.py -- sensors \
#       --scene SCENE.json --out SENSORS.csv [--spacing 0.25] [--offset 0.002]
#   blender -b --factory-startup -P validation/cycles_irradiance.py -- render \
#       --scene SCENE.json --camera NAME --out IMAGE.exr --info INFO.json [--width 320] [--height 180] \
#       [--samples 256] [--seed 0] [--sky SKY.exr --sky-json SKY.json]
#
# `render` renders one of the scene file's cameras into a multilayer EXR (Combined in cd/m², and IndexMA: each
# fly material's region number, named in INFO.json); with --sky, the world is fly's own sky and sun as
# `fly sky --scene SCENE --json --out SKY.exr` writes them (fly_sky_world below), and the scene's site, time
# and sky keys are allowed. validation/validate_images.py drives it.
#
# SCENE is a fly scene file (docs/scene-format.md), of which this script reads the subset a Lambertian
# comparison needs: `models` (file, translation, rotationDeg, scale), `lights` (point and directional),
# `overrides` by material name (diffuse; reflection and transmission only as zero; bumpScale, which a
# Lambertian surface ignores; emission; the preset clear-glass alone, a thin Fresnel pane), `cameras`. Anything else is refused with a message, so that a comparison never
# silently differs from what fly computes.
#
# Materials. Every material becomes Lambertian with fly's diffuse albedo: the override's `diffuse`, else
# (1 − metallicFactor) × baseColorFactor, times the base-colour texture (sRGB-decoded by Blender, with the
# importer's UV set, KHR_texture_transform and sampler) and COLOR_0, as fly's glTF conversion defines it.
# Coverage (base colour alpha × texture alpha × COLOR_0 alpha) is kept: alphaMode MASK is a cut-out where
# coverage < alphaCutoff, BLEND lets 1 − coverage of the light pass straight through (Cycles' Transparent
# BSDF, which is fly's model exactly). Emission (emissiveFactor × KHR_materials_emissive_strength, cd/m²) is
# Cycles' emission strength: Cycles is linear, so its W/m²/sr stand for cd/m² throughout, as its W/m² of a
# sun stand for lux.
#
# Faces. Cycles shades both faces of every surface. fly, following glTF, gives the back face of a one-sided
# material (doubleSided false) no reflection and no emission: it only blocks light (raytracer/integrator.h).
# Here a Backfacing switch gives such back faces a black Lambertian surface, which is the same.
#
# Normals. fly's baker shades with the files' vertex normals (interpolated), the geometric normal deciding
# the side; --normals shading (the default) imports them so that Cycles does too; --normals geometric imports
# flat shading, for a fly that shades with geometric normals. Normal maps are not used (Lambertian mode: fly's
# overrides set bumpScale 0).
#
# Lights. A glTF or scene directional light of E lux is a Cycles sun of strength E (W/m² on a surface facing
# it) and angle 0 (a delta direction, as in fly; --sun-angle-deg changes it). A scene light may carry
# "angleDeg", a key of this script's own (not fly's), for the angular diameter of fly's sun disc (0.533°),
# which the driver writes where it spells out fly's sun of a site and time as a directional light. A point light of I cd is a
# Cycles point lamp of power 4π I W with radius 0: Cycles' point lamp of power P has radiant intensity
# P / (4π) W/sr (docs/validation.md checks this against the analytic sphere). The glTF importer's "COMPAT"
# lighting mode converts KHR_lights_punctual this way; lights with `range` or spots are refused. The world
# is black, unless the scene carries "world": {"skyRadianceCdM2": L}, a key of this script's own (not fly's)
# for a sky of uniform radiance L above the horizon and black below (fly's CIE sky of type 5, which the
# driver spells out so).
#
# Portals. The scene file's `portals` (docs/scene-format.md) become Cycles portal lights: an area light of shape
# RECTANGLE over each quad (which must be a rectangle: Cycles' area lights are), marked is_portal, facing
# (its −Z) into the room. Which side is the room is decided as fly decides it (raytracer/integrator.h, "Sky
# portals"): rays from the portal's centre over the upper hemisphere on each side, the room's side being the
# one whose rays escape less often. A portal changes Cycles' sampling of the world, not its result.
#
# Measurement. Each sensor is a square of side --quad-size metres centred on its point, facing its normal,
# invisible to every ray that the bake traces (diffuse, glossy, transmission, shadow, volume; the scene has no
# camera), so that it changes nothing in the scene. It is baked with bake type DIFFUSE, passes direct + indirect without colour: the value is
# the irradiance over π of a Lambertian receiver (docs/validation.md checks the factor against a plane under a
# sun), so E = π × value. Each sensor owns a block of --pixels × --pixels texels; the texels are independent
# Monte-Carlo estimates of the same irradiance (Cycles scrambles its sample sequence per pixel), so the
# sensor's value is their mean and its standard error their standard deviation / √(texels). The luminance of
# each texel's colour (Rec.709 weights, as fly's illuminance_lux) is the texel's value.
#
# Render settings: no clamping, no light threshold, no adaptive sampling, no denoising, bounce limits of
# 1024 (paths end by Cycles' Russian roulette, which is unbiased), so that Cycles' estimate is unbiased.
import argparse
import array
import json
import math
import os
import struct
import sys
import time

import bpy
import mathutils
import numpy

# Blender 3.4's glTF importer uses numpy.bool when it keeps the files' normals (set_poly_smoothing), an alias
# that numpy 1.24 (Debian 12) removed: restore it, as the builtin it always stood for.
if "bool" not in numpy.__dict__:
    numpy.bool = bool

REC709_Y = (0.2126, 0.7152, 0.0722)
UNTEXTURED = False  # --untextured: albedo = the factor alone, every surface opaque
SUPPORTED_OVERRIDE_KEYS = {"material", "diffuse", "reflection", "transmission", "bumpScale", "emission",
                           "doubleSided", "preset"}
# The one preset the reference reproduces: fly's clear glass, a thin pane (sdb/material.h, hasClearTransmission)
# that reflects F(θ) as a mirror, F Schlick's approximation of the Fresnel reflectance at IOR 1.52, and lets
# T(θ) pass straight through: the lossless slab of two Fresnel faces scaled to 1 − F0 at normal incidence
# (base/clear_pane.h; the preset's transmission and reflection colours are white).
CLEAR_GLASS = "clear-glass"
CLEAR_GLASS_IOR = 1.52


def fail(message):
    print("cycles_irradiance: error: " + message, file=sys.stderr)
    sys.exit(3)


# glTF (+Y up) to Blender (+Z up), the glTF importer's convention: (x, y, z) -> (x, -z, y).
GLTF_TO_BLENDER = mathutils.Matrix(((1, 0, 0, 0), (0, 0, -1, 0), (0, 1, 0, 0), (0, 0, 0, 1)))
BLENDER_TO_GLTF = GLTF_TO_BLENDER.inverted()


def to_blender(v):
    return mathutils.Vector((v[0], -v[2], v[1]))


def to_gltf(v):
    return (v[0], v[2], -v[1])


def read_gltf_json(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == b"glTF":
        length = struct.unpack("<I", data[12:16])[0]
        return json.loads(data[20:20 + length].decode("utf-8"))
    return json.loads(data.decode("utf-8-sig"))


def load_scene_file(path, fly_daylight=False):
    """fly_daylight: the scene's site, time and sky are allowed, because the caller gives Cycles fly's own sky
    and sun (`render --sky`); otherwise the world must be black or the uniform `world` sky."""
    with open(path, encoding="utf-8-sig") as f:
        scene = json.load(f)
    base = os.path.dirname(os.path.abspath(path))
    allowed = {"fly", "models", "lights", "overrides", "bake", "sky", "world", "portals", "cameras"}
    if fly_daylight:
        allowed |= {"site", "time"}
    for key in scene:
        if key not in allowed:
            fail(f"{path}: key '{key}' is not supported by the Cycles reference (supported: {sorted(allowed)})")
    sky = scene.get("sky", {})
    if not fly_daylight and (sky.get("model", "none") != "none" or sky.get("sun", False)):
        fail(f"{path}: only a black world is supported (sky.model none, no sky sun); use a directional light")
    if fly_daylight and scene.get("site", {}).get("northAngle", 0) != 0:
        fail(f"{path}: the Cycles reference takes fly's sky image with north along −Z (site.northAngle 0)")
    for key in scene.get("world", {}):
        if key != "skyRadianceCdM2":
            fail(f"{path}: world key '{key}' is not supported (supported: skyRadianceCdM2)")
    for m in scene.get("models", []):
        m["file"] = m["file"] if os.path.isabs(m["file"]) else os.path.join(base, m["file"])
    return scene


def clear_blend():
    for collection in (bpy.data.objects, bpy.data.meshes, bpy.data.materials, bpy.data.lights,
                       bpy.data.cameras, bpy.data.images):
        for item in list(collection):
            collection.remove(item)


def placement_matrix(model):
    """parentFromLocal = T · R · S in glTF space, R = Rz · Ry · Rx (docs/scene-format.md, models)."""
    t = model.get("translation", [0, 0, 0])
    r = [math.radians(a) for a in model.get("rotationDeg", [0, 0, 0])]
    s = model.get("scale", 1)
    if not isinstance(s, list):
        s = [s, s, s]
    T = mathutils.Matrix.Translation(t)
    R = (mathutils.Matrix.Rotation(r[2], 4, "Z") @ mathutils.Matrix.Rotation(r[1], 4, "Y")
         @ mathutils.Matrix.Rotation(r[0], 4, "X"))
    S = mathutils.Matrix.Diagonal((s[0], s[1], s[2], 1))
    return T @ R @ S


def import_models(scene, normals):
    """Imports every model; returns {blender material name: glTF material dict}."""
    materials = {}
    for model in scene.get("models", []):
        path = model["file"]
        if not os.path.exists(path):
            fail(f"model file {path} does not exist")
        before = set(bpy.data.objects)
        mats_before = set(bpy.data.materials)
        result = bpy.ops.import_scene.gltf(filepath=path, import_shading="FLAT" if normals == "geometric"
                                           else "NORMALS", convert_lighting_mode="COMPAT")
        if result != {"FINISHED"}:
            fail(f"Blender's glTF importer could not read {path}")
        new_objects = [o for o in bpy.data.objects if o not in before]
        gltf = read_gltf_json(path)
        gltf_materials = gltf.get("materials", [])
        for mat in bpy.data.materials:
            if mat in mats_before:
                continue
            base = mat.name
            match = [g for i, g in enumerate(gltf_materials) if g.get("name", f"Material_{i}") == base]
            if not match and len(base) > 4 and base[-4] == "." and base[-3:].isdigit():
                base = base[:-4]
                match = [g for i, g in enumerate(gltf_materials) if g.get("name", f"Material_{i}") == base]
            if not match:
                fail(f"{path}: cannot match Blender material '{mat.name}' to a glTF material")
            materials[mat.name] = dict(match[0], flyName=base)
        placement = GLTF_TO_BLENDER @ placement_matrix(model) @ BLENDER_TO_GLTF
        root = bpy.data.objects.new("placement:" + os.path.basename(path), None)
        bpy.context.scene.collection.objects.link(root)
        root.matrix_world = placement
        for o in new_objects:
            if o.parent is None:
                world = o.matrix_world.copy()
                o.parent = root
                o.matrix_parent_inverse = mathutils.Matrix.Identity(4)
                o.matrix_basis = world
    return materials


def add_scene_lights(scene, sun_angle_rad):
    for i, light in enumerate(scene.get("lights", [])):
        kind = light.get("type")
        for key in light:
            if key not in ("name", "type", "position", "direction", "intensity", "color", "angleDeg"):
                fail(f"lights[{i}]: key '{key}' is not supported by the Cycles reference")
        colour = light.get("color", [1, 1, 1])
        name = light.get("name", f"light {i}")
        if kind == "point":
            data = bpy.data.lights.new(name, "POINT")
            data.energy = 4.0 * math.pi * light["intensity"]
            obj = bpy.data.objects.new(name, data)
            obj.location = to_blender(light["position"])
        elif kind == "directional":
            data = bpy.data.lights.new(name, "SUN")
            data.energy = light["intensity"]
            obj = bpy.data.objects.new(name, data)
            d = to_blender(light.get("direction", [0, -1, 0])).normalized()
            obj.rotation_euler = d.to_track_quat("-Z", "Y").to_euler()
        else:
            fail(f"lights[{i}]: type '{kind}' is not supported by the Cycles reference (point, directional)")
        data.color = colour
        if "angleDeg" in light:
            data["flyAngleRad"] = math.radians(light["angleDeg"])
        bpy.context.scene.collection.objects.link(obj)
    for obj in bpy.data.objects:
        if obj.type != "LIGHT":
            continue
        data = obj.data
        if data.type == "SUN":
            data.angle = data.get("flyAngleRad", sun_angle_rad)
        elif data.type == "POINT":
            data.shadow_soft_size = 0.0
        else:
            fail(f"light '{obj.name}' of type {data.type} is not supported by the Cycles reference")
        data.cycles.max_bounces = 1024
        data.cycles.use_multiple_importance_sampling = True


def add_scene_portals(scene):
    """Each of the scene's portals as a Cycles portal light (see Portals above); call after the models are
    imported, since the room's side is found by casting rays against them."""
    portals = scene.get("portals", [])
    if not portals:
        return
    bpy.context.view_layer.update()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    for i, portal in enumerate(portals):
        name = portal.get("name", f"portal {i}")
        corners = [to_blender(c) for c in portal["corners"]]
        if len(corners) != 4:
            fail(f"portals[{i}] '{name}': only quads (4 corners) are supported by the Cycles reference")
        u, v = corners[1] - corners[0], corners[3] - corners[0]
        width, height = u.length, v.length
        diagonal = corners[2] - corners[0]
        if abs(u.dot(v)) > 1e-4 * width * height or (diagonal - u - v).length > 1e-4 * max(width, height):
            fail(f"portals[{i}] '{name}': the Cycles reference needs a rectangle (Cycles' area lights are)")
        centre = sum(corners, mathutils.Vector()) / 4.0
        normal = u.cross(v).normalized()

        def escaped(side):
            """How many of 256 rays from just off the centre to `side` over the upper hemisphere (Blender +Z)
            hit nothing."""
            origin = centre + side * 1e-4 * max(1.0, max(abs(c) for c in centre))
            count = 0
            for k in range(256):
                z = 1.0 - (2.0 * k + 1.0) / 256
                r = math.sqrt(max(0.0, 1.0 - z * z))
                d = mathutils.Vector((r * math.cos(2.39996323 * k), r * math.sin(2.39996323 * k), z))
                if d.dot(side) > 0.0 and d.z > 0.0:
                    hit = bpy.context.scene.ray_cast(depsgraph, origin, d)[0]
                    count += 0 if hit else 1
            return count

        inward = -normal if escaped(normal) > escaped(-normal) else normal
        x_axis = u.normalized()
        z_axis = -inward
        y_axis = z_axis.cross(x_axis)
        data = bpy.data.lights.new(name, "AREA")
        data.shape = "RECTANGLE"
        data.size = width
        data.size_y = height
        data.cycles.is_portal = True
        obj = bpy.data.objects.new(name, data)
        obj.matrix_world = mathutils.Matrix.Translation(centre) @ mathutils.Matrix(
            (x_axis, y_axis, z_axis)).transposed().to_4x4()
        bpy.context.scene.collection.objects.link(obj)
        at = tuple(round(c, 3) for c in to_gltf(centre))
        facing = tuple(round(c, 3) for c in to_gltf(inward))
        print(f"cycles_irradiance: portal '{name}', {width:.3f} × {height:.3f} m at {at} (glTF frame), facing {facing}")


def upstream_node(socket, node_type):
    """The first node of node_type found by walking links upstream of an input socket."""
    seen = set()
    stack = [link.from_node for link in socket.links]
    while stack:
        node = stack.pop()
        if node.name in seen:
            continue
        seen.add(node.name)
        if node.type == node_type:
            return node
        for inp in node.inputs:
            stack.extend(link.from_node for link in inp.links)
    return None


def matches(pattern, name):
    return name.startswith(pattern[:-1]) if pattern.endswith("*") else name == pattern


def material_overrides(scene, fly_name):
    result = {}
    for i, o in enumerate(scene.get("overrides", [])):
        if "material" not in o:
            fail(f"overrides[{i}]: only overrides by material name are supported by the Cycles reference")
        for key in o:
            if key not in SUPPORTED_OVERRIDE_KEYS:
                fail(f"overrides[{i}]: key '{key}' is not supported by the Cycles reference")
        if o.get("preset", CLEAR_GLASS) != CLEAR_GLASS or (o.get("preset") and len(o) > 2):
            fail(f"overrides[{i}]: of the presets only '{CLEAR_GLASS}', alone, is supported by the Cycles reference")
        for key in ("reflection", "transmission"):
            if key in o and any(c != 0 for c in o[key]):
                fail(f"overrides[{i}]: {key} must be [0, 0, 0] (the Cycles reference is Lambertian)")
        if matches(o["material"], fly_name):
            result.update(o)
    return result


def lambertian_material(mat, gltf_mat, scene):
    """Rebuilds mat as fly's Lambertian counterpart of the glTF material (see the header)."""
    tree = mat.node_tree
    nodes, links = tree.nodes, tree.links
    principled = next((n for n in nodes if n.type == "BSDF_PRINCIPLED"), None)
    if principled is None:
        fail(f"material '{mat.name}': the importer made no Principled BSDF (unlit or specular-glossiness "
             "materials are not supported)")
    override = material_overrides(scene, gltf_mat["flyName"])
    pbr = gltf_mat.get("pbrMetallicRoughness", {})
    factor = pbr.get("baseColorFactor", [1, 1, 1, 1])
    metallic = pbr.get("metallicFactor", 1.0)
    diffuse = override.get("diffuse", [(1.0 - metallic) * c for c in factor[:3]])
    if "emissiveTexture" in gltf_mat:
        fail(f"material '{mat.name}': emissive textures are not supported by the Cycles reference")
    emissive = gltf_mat.get("emissiveFactor", [0, 0, 0])
    strength = gltf_mat.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get(
        "emissiveStrength", 1.0)
    emission = override.get("emission", [strength * c for c in emissive])
    double_sided = override.get("doubleSided", gltf_mat.get("doubleSided", False))
    alpha_mode = gltf_mat.get("alphaMode", "OPAQUE")
    cutoff = gltf_mat.get("alphaCutoff", 0.5)

    texture = upstream_node(principled.inputs["Base Color"], "TEX_IMAGE")
    vertex_colour = upstream_node(principled.inputs["Base Color"], "VERTEX_COLOR")
    if UNTEXTURED:
        texture, vertex_colour, alpha_mode = None, None, "OPAQUE"
    alpha_links = principled.inputs["Alpha"].links
    alpha_socket = alpha_links[0].from_socket if alpha_links else None
    alpha_value = principled.inputs["Alpha"].default_value
    output = next(n for n in nodes if n.type == "OUTPUT_MATERIAL")
    for link in list(output.inputs["Surface"].links):
        links.remove(link)
    if override.get("preset") == CLEAR_GLASS:
        # F(θ) and T(θ) from |cos θ|, the same from either side of the pane, as fly takes them (sdb/material.cpp,
        # reflectionAt and clearTransmittanceAt). Cycles' Fresnel node would take the back face as the inside of
        # a solid and reflect totally beyond 41°, closing the window to the sun.
        def math(op, a, b=None):
            n = nodes.new("ShaderNodeMath")
            n.operation = op
            for i, x in enumerate((a, b)):
                if isinstance(x, (int, float)):
                    n.inputs[i].default_value = x
                elif x is not None:
                    links.new(x, n.inputs[i])
            return n.outputs[0]

        geometry = nodes.new("ShaderNodeNewGeometry")
        dot = nodes.new("ShaderNodeVectorMath")
        dot.operation = "DOT_PRODUCT"
        links.new(geometry.outputs["Incoming"], dot.inputs[0])
        links.new(geometry.outputs["Normal"], dot.inputs[1])
        n = CLEAR_GLASS_IOR
        f0 = ((n - 1) / (n + 1)) ** 2
        c = math("ABSOLUTE", dot.outputs["Value"])
        fresnel = math("ADD", math("MULTIPLY", math("POWER", math("SUBTRACT", 1.0, c), 5.0), 1 - f0), f0)
        # 1 − R of one face for s and p polarisation (the Fresnel equations, θt from Snell's law): 4 n c c_t /
        # (c + n c_t)² and 4 n c c_t / (n c + c_t)²; the lossless slab passes (1 − R) / (1 + R) of each, and
        # its mean over the two, times (1 + F0) = (1 − F0) / S(0), is the pane's T, at most 1 − F(θ).
        ct = math("SQRT", math("SUBTRACT", 1.0, math("DIVIDE", math("SUBTRACT", 1.0, math("MULTIPLY", c, c)), n * n)))
        k = math("MULTIPLY", math("MULTIPLY", c, ct), 4.0 * n)
        slab = None
        for first, second in ((c, math("MULTIPLY", ct, n)), (math("MULTIPLY", c, n), ct)):
            s = math("ADD", first, second)
            through = math("DIVIDE", k, math("MULTIPLY", s, s))
            half = math("MULTIPLY", math("DIVIDE", through, math("SUBTRACT", 2.0, through)), 0.5)
            slab = half if slab is None else math("ADD", slab, half)
        transmittance = math("MINIMUM", math("MULTIPLY", slab, 1 + f0), math("SUBTRACT", 1.0, fresnel))
        mirror = nodes.new("ShaderNodeBsdfGlossy")
        mirror.distribution = "SHARP"
        links.new(fresnel, mirror.inputs["Color"])
        through = nodes.new("ShaderNodeBsdfTransparent")
        links.new(transmittance, through.inputs["Color"])
        pane = nodes.new("ShaderNodeAddShader")
        links.new(through.outputs["BSDF"], pane.inputs[0])
        links.new(mirror.outputs["BSDF"], pane.inputs[1])
        links.new(pane.outputs["Shader"], output.inputs["Surface"])
        return {"name": mat.name, "preset": CLEAR_GLASS, "doubleSided": True}

    # Albedo = diffuse × texture × vertex colour.
    albedo = None
    for source in (texture, vertex_colour):
        if source is None:
            continue
        if albedo is None:
            albedo = source.outputs["Color"]
        else:
            mul = nodes.new("ShaderNodeMixRGB")
            mul.blend_type = "MULTIPLY"
            mul.inputs["Fac"].default_value = 1.0
            links.new(albedo, mul.inputs["Color1"])
            links.new(source.outputs["Color"], mul.inputs["Color2"])
            albedo = mul.outputs["Color"]
    lambert = nodes.new("ShaderNodeBsdfDiffuse")
    lambert.inputs["Roughness"].default_value = 0.0
    if albedo is None:
        lambert.inputs["Color"].default_value = list(diffuse) + [1.0]
    else:
        mul = nodes.new("ShaderNodeMixRGB")
        mul.blend_type = "MULTIPLY"
        mul.inputs["Fac"].default_value = 1.0
        links.new(albedo, mul.inputs["Color1"])
        mul.inputs["Color2"].default_value = list(diffuse) + [1.0]
        links.new(mul.outputs["Color"], lambert.inputs["Color"])
    surface = lambert.outputs["BSDF"]
    if any(c > 0 for c in emission):
        emit = nodes.new("ShaderNodeEmission")
        emit.inputs["Color"].default_value = list(emission) + [1.0]
        emit.inputs["Strength"].default_value = 1.0
        add = nodes.new("ShaderNodeAddShader")
        links.new(surface, add.inputs[0])
        links.new(emit.outputs["Emission"], add.inputs[1])
        surface = add.outputs["Shader"]
    if not double_sided:
        geometry = nodes.new("ShaderNodeNewGeometry")
        black = nodes.new("ShaderNodeBsdfDiffuse")
        black.inputs["Color"].default_value = (0, 0, 0, 1)
        mix = nodes.new("ShaderNodeMixShader")
        links.new(geometry.outputs["Backfacing"], mix.inputs["Fac"])
        links.new(surface, mix.inputs[1])
        links.new(black.outputs["BSDF"], mix.inputs[2])
        surface = mix.outputs["Shader"]
    if alpha_mode in ("MASK", "BLEND") and (alpha_socket is not None or alpha_value < 1.0):
        coverage = alpha_socket
        if alpha_mode == "MASK":
            below = nodes.new("ShaderNodeMath")
            below.operation = "LESS_THAN"
            if coverage is None:
                below.inputs[0].default_value = alpha_value
            else:
                links.new(coverage, below.inputs[0])
            below.inputs[1].default_value = cutoff
            opaque = nodes.new("ShaderNodeMath")
            opaque.operation = "SUBTRACT"
            opaque.inputs[0].default_value = 1.0
            links.new(below.outputs[0], opaque.inputs[1])
            coverage = opaque.outputs[0]
        transparent = nodes.new("ShaderNodeBsdfTransparent")
        mix = nodes.new("ShaderNodeMixShader")
        if coverage is None:
            mix.inputs["Fac"].default_value = alpha_value
        else:
            links.new(coverage, mix.inputs["Fac"])
        links.new(transparent.outputs["BSDF"], mix.inputs[1])
        links.new(surface, mix.inputs[2])
        surface = mix.outputs["Shader"]
    links.new(surface, output.inputs["Surface"])
    return {"name": mat.name, "diffuse": list(diffuse), "texture": texture.image.name if texture else None,
            "vertexColour": vertex_colour is not None, "emission": list(emission),
            "doubleSided": double_sided, "alphaMode": alpha_mode}


def default_material():
    """fly's material for primitives without one: diffuse 0.8 grey, one-sided (glTF's default material)."""
    mat = bpy.data.materials.new("fly-default")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    for n in list(nodes):
        nodes.remove(n)
    output = nodes.new("ShaderNodeOutputMaterial")
    nodes.new("ShaderNodeBsdfPrincipled")
    links = mat.node_tree.links
    links.new(nodes["Principled BSDF"].outputs[0], output.inputs["Surface"])
    return mat


def setup_materials(scene, gltf_materials):
    report = []
    fallback = None
    for obj in bpy.data.objects:
        if obj.type != "MESH":
            continue
        if not obj.material_slots or any(s.material is None for s in obj.material_slots):
            if fallback is None:
                fallback = default_material()
                gltf_materials[fallback.name] = {"name": "default", "flyName": "default",
                                                 "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1],
                                                                          "metallicFactor": 0.0}}
            if not obj.material_slots:
                obj.data.materials.append(fallback)
            for s in obj.material_slots:
                if s.material is None:
                    s.material = fallback
    for mat in list(bpy.data.materials):
        if mat.name in gltf_materials:
            report.append(lambertian_material(mat, gltf_materials[mat.name], scene))
    return report


def configure_cycles(samples, seed, threads, sky_radiance=0.0):
    s = bpy.context.scene
    s.render.engine = "CYCLES"
    c = s.cycles
    c.device = "CPU"
    c.samples = samples
    c.seed = seed
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.max_bounces = 1024
    c.diffuse_bounces = 1024
    c.glossy_bounces = 1024
    c.transmission_bounces = 1024
    c.volume_bounces = 0
    c.transparent_max_bounces = 1024
    c.min_light_bounces = 0
    c.min_transparent_bounces = 0
    s.render.threads_mode = "FIXED" if threads > 0 else "AUTO"
    if threads > 0:
        s.render.threads = threads
    s.view_settings.view_transform = "Standard"
    s.view_settings.look = "None"
    s.view_settings.exposure = 0.0
    s.view_settings.gamma = 1.0
    world = bpy.data.worlds.new("black") if not bpy.data.worlds else bpy.data.worlds[0]
    world.use_nodes = True
    background = next(n for n in world.node_tree.nodes if n.type == "BACKGROUND")
    background.inputs["Color"].default_value = (0, 0, 0, 1)
    background.inputs["Strength"].default_value = 0.0
    if sky_radiance > 0.0:
        # Uniform radiance above the horizon, black below, as fly's sky (rdb/trace_rdb.h TraceSky): the world's
        # Generated coordinate is the ray's direction, whose Blender z is glTF's (and fly's) +Y.
        nodes, links = world.node_tree.nodes, world.node_tree.links
        coords = nodes.new("ShaderNodeTexCoord")
        split = nodes.new("ShaderNodeSeparateXYZ")
        above = nodes.new("ShaderNodeMath")
        above.operation = "GREATER_THAN"
        above.inputs[1].default_value = 0.0
        level = nodes.new("ShaderNodeMath")
        level.operation = "MULTIPLY"
        level.inputs[1].default_value = sky_radiance
        links.new(coords.outputs["Generated"], split.inputs["Vector"])
        links.new(split.outputs["Z"], above.inputs[0])
        links.new(above.outputs["Value"], level.inputs[0])
        links.new(level.outputs["Value"], background.inputs["Strength"])
        background.inputs["Color"].default_value = (1, 1, 1, 1)
    s.world = world


def fly_sky_world(sky_exr, sky_json):
    """The world as fly's sky and sun: `fly sky --json --out SKY.exr` writes the sky dome as an equidistant
    fisheye looking up (zenith at the centre, horizon on the circle, north up, east left; cli/sky_image.h) in
    cd/m², with the sun's disc added to the pixels it covers. The disc is taken out of the image and becomes a
    Cycles sun lamp of fly's angular diameter (0.533°) whose strength and colour are the disc's normal
    illuminance per channel (lux); the rest is looked up per ray direction from the image, black below the
    horizon as in fly (rdb/trace_rdb.h, TraceSky: the ground is geometry). Returns a summary for the log."""
    with open(sky_json) as f:
        meta = json.load(f)
    image = bpy.data.images.load(sky_exr)
    image.colorspace_settings.name = "Non-Color"
    size = image.size[0]
    px = numpy.empty(size * size * 4, dtype=numpy.float32)
    image.pixels.foreach_get(px)
    px = px.reshape(size, size, 4)  # Blender's rows run bottom-up: row k is fly's row size − 1 − k
    lum = px[..., 0] * REC709_Y[0] + px[..., 1] * REC709_Y[1] + px[..., 2] * REC709_Y[2]
    zenith = math.radians(meta["sun_apparent_zenith_deg"])
    azimuth = math.radians(meta["sun_azimuth_deg"])
    # East, north, up; with site.northAngle 0 these are Blender's +X, +Y, +Z (glTF +X, −Z, +Y).
    to_sun = mathutils.Vector((math.sin(zenith) * math.sin(azimuth), math.sin(zenith) * math.cos(azimuth),
                               math.cos(zenith)))
    summary = {"sky_dhi_lux": meta["diffuse_horizontal_illuminance_lux"]}
    if to_sun.z > 0.0 and meta.get("direct_normal_illuminance_lux", 0.0) > 0.0:
        half = size / 2.0
        r = zenith / (math.pi / 2.0)
        h = math.hypot(to_sun.x, to_sun.y)
        col = half - to_sun.x / h * r * half
        row_up = half + to_sun.y / h * r * half  # from the bottom, as Blender stores it
        c0, r0 = int(col), int(row_up)
        rows, cols = numpy.mgrid[0:size, 0:size]
        dist = numpy.hypot(cols + 0.5 - col, rows + 0.5 - row_up)
        reach = 2 + math.radians(0.533) / (math.pi / size)
        near = dist <= reach
        ring = (dist > reach + 1) & (dist <= reach + 3)
        background = numpy.median(lum[ring])
        disc = near & (lum > 20.0 * background)
        sky_rgb = px[ring][:, :3].mean(axis=0)
        # Each disc pixel's excess over the surrounding sky × its solid angle (π/size)² sinc θ sums to the
        # normal illuminance.
        x = (cols + 0.5 - half) / half
        y = (rows + 0.5 - half) / half
        theta = numpy.hypot(x, y) * (math.pi / 2.0)
        omega = (math.pi / size) ** 2 * numpy.where(theta > 1e-8, numpy.sin(theta) / numpy.maximum(theta, 1e-8), 1.0)
        excess = (px[..., :3] - sky_rgb) * omega[..., None]
        sun_rgb = excess[disc].sum(axis=0)
        px[disc, :3] = sky_rgb
        image.pixels.foreach_set(px.ravel())
        image.pack()
        sun_y = float(sum(REC709_Y[k] * sun_rgb[k] for k in range(3)))
        data = bpy.data.lights.new("fly-sun", "SUN")
        data.energy = sun_y
        data.color = [float(c) / sun_y for c in sun_rgb]
        data.angle = math.radians(0.533)
        data.cycles.max_bounces = 1024
        obj = bpy.data.objects.new("fly-sun", data)
        obj.rotation_euler = (-to_sun).to_track_quat("-Z", "Y").to_euler()
        bpy.context.scene.collection.objects.link(obj)
        summary.update(sun_dni_lux=sun_y, sun_dni_lux_fly=meta["direct_normal_illuminance_lux"],
                       sun_pixels=int(disc.sum()), sun_rgb=[float(c) for c in sun_rgb])
    world = bpy.data.worlds.new("fly-sky")
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    background = next(n for n in nodes if n.type == "BACKGROUND")
    background.inputs["Strength"].default_value = 1.0

    def math_node(op, a, b=None):
        n = nodes.new("ShaderNodeMath")
        n.operation = op
        for k, v in enumerate((a, b)):
            if v is None:
                continue
            if isinstance(v, (int, float)):
                n.inputs[k].default_value = v
            else:
                links.new(v, n.inputs[k])
        return n.outputs[0]

    # The world's Generated coordinate is the ray's direction (Blender axes).
    coords = nodes.new("ShaderNodeTexCoord")
    split = nodes.new("ShaderNodeSeparateXYZ")
    links.new(coords.outputs["Generated"], split.inputs["Vector"])
    dx, dy, dz = split.outputs["X"], split.outputs["Y"], split.outputs["Z"]
    horizontal = math_node("ADD", math_node("SQRT", math_node("ADD", math_node("MULTIPLY", dx, dx),
                                                                  math_node("MULTIPLY", dy, dy))), 1e-9)
    # Fisheye radius over the horizontal length: (θ / (π/2)) / h, θ = acos(z).
    scale = math_node("DIVIDE", math_node("DIVIDE", math_node("ARCCOSINE", dz), math.pi / 2.0), horizontal)
    u = math_node("SUBTRACT", 0.5, math_node("MULTIPLY", math_node("MULTIPLY", dx, scale), 0.5))
    v = math_node("ADD", 0.5, math_node("MULTIPLY", math_node("MULTIPLY", dy, scale), 0.5))
    uv = nodes.new("ShaderNodeCombineXYZ")
    links.new(u, uv.inputs["X"])
    links.new(v, uv.inputs["Y"])
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = image
    tex.interpolation = "Linear"
    tex.extension = "CLIP"
    links.new(uv.outputs["Vector"], tex.inputs["Vector"])
    above = math_node("GREATER_THAN", dz, 0.0)
    mask = nodes.new("ShaderNodeMixRGB")  # black below the horizon, the image above it
    links.new(above, mask.inputs["Fac"])
    mask.inputs["Color1"].default_value = (0, 0, 0, 1)
    links.new(tex.outputs["Color"], mask.inputs["Color2"])
    links.new(mask.outputs["Color"], background.inputs["Color"])
    world.cycles.sampling_method = "MANUAL"
    world.cycles.sample_map_resolution = 1024
    bpy.context.scene.world = world
    return summary


def read_sensors(path):
    with open(path) as f:
        lines = [ln.rstrip("\r\n") for ln in f if ln.strip()]
    header = [h.strip() for h in lines[0].split(",")]
    idx = {k: header.index(k) for k in ("x", "y", "z", "nx", "ny", "nz")}
    sensors = []
    for ln in lines[1:]:
        f = ln.split(",")
        p = [float(f[idx[k]]) for k in ("x", "y", "z")]
        n = [float(f[idx[k]]) for k in ("nx", "ny", "nz")]
        sensors.append((p, n, ln))
    return lines[0], sensors


def sensor_object(sensors, quad_size, pixels):
    """Tiny quads (Blender space), one texel block per sensor; returns (object, image, block origins)."""
    count = len(sensors)
    cell = pixels + 1
    per_row = max(1, math.ceil(math.sqrt(count)))
    rows = math.ceil(count / per_row)
    width, height = per_row * cell, rows * cell
    verts, faces, uvs, origins = [], [], [], []
    h = 0.5 * quad_size
    for i, (p, n, _) in enumerate(sensors):
        centre = to_blender(p)
        normal = to_blender(n).normalized()
        helper = mathutils.Vector((1, 0, 0)) if abs(normal.x) < 0.9 else mathutils.Vector((0, 1, 0))
        t = normal.cross(helper).normalized()
        b = normal.cross(t)  # t × b = n: the corners below wind counter-clockwise about n
        base = len(verts)
        verts += [centre - h * t - h * b, centre + h * t - h * b, centre + h * t + h * b, centre - h * t + h * b]
        faces.append((base, base + 1, base + 2, base + 3))
        ox, oy = (i % per_row) * cell, (i // per_row) * cell
        origins.append((ox, oy))
        u0, v0, u1, v1 = ox / width, oy / height, (ox + pixels) / width, (oy + pixels) / height
        uvs += [(u0, v0), (u1, v0), (u1, v1), (u0, v1)]
    mesh = bpy.data.meshes.new("fly-sensors")
    mesh.from_pydata([tuple(v) for v in verts], [], faces)
    layer = mesh.uv_layers.new(name="sensors")
    for loop in mesh.loops:
        layer.data[loop.index].uv = uvs[loop.vertex_index]
    for poly in mesh.polygons:
        poly.use_smooth = False
    obj = bpy.data.objects.new("fly-sensors", mesh)
    bpy.context.scene.collection.objects.link(obj)
    # Seen by no ray of the scene; camera visibility stays on, since Cycles leaves out an object that no
    # ray can see, and this scene has no camera.
    for attr in ("visible_diffuse", "visible_glossy", "visible_transmission",
                 "visible_volume_scatter", "visible_shadow"):
        setattr(obj, attr, False)
    image = bpy.data.images.new("fly-sensors", width, height, alpha=True, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    mat = bpy.data.materials.new("fly-sensor")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    for n in list(nodes):
        nodes.remove(n)
    out = nodes.new("ShaderNodeOutputMaterial")
    bsdf = nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (1, 1, 1, 1)
    mat.node_tree.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = image
    nodes.active = tex
    obj.data.materials.append(mat)
    return obj, image, origins


def cmd_irradiance(args):
    global UNTEXTURED
    UNTEXTURED = args.untextured
    start = time.time()
    scene = load_scene_file(args.scene)
    clear_blend()
    gltf_materials = import_models(scene, args.normals)
    add_scene_lights(scene, math.radians(args.sun_angle_deg))
    add_scene_portals(scene)
    report = setup_materials(scene, gltf_materials)
    header, sensors = read_sensors(args.points)
    configure_cycles(args.samples, args.seed, args.threads, scene.get("world", {}).get("skyRadianceCdM2", 0.0))
    obj, image, origins = sensor_object(sensors, args.quad_size, args.pixels)
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    setup_s = time.time() - start
    bpy.context.scene.render.bake.margin = 0
    bpy.ops.object.bake(type="DIFFUSE", pass_filter={"DIRECT", "INDIRECT"}, margin=0, use_clear=True,
                        target="IMAGE_TEXTURES")
    bake_s = time.time() - start - setup_s
    width, height = image.size
    px = array.array("f", bytes(4 * 4 * width * height))
    image.pixels.foreach_get(px)
    k = args.pixels
    rows = []
    for (p, n, line), (ox, oy) in zip(sensors, origins):
        values = []
        for j in range(oy, oy + k):
            for i in range(ox, ox + k):
                o = 4 * (j * width + i)
                values.append(math.pi * (REC709_Y[0] * px[o] + REC709_Y[1] * px[o + 1] + REC709_Y[2] * px[o + 2]))
        m = len(values)
        mean = sum(values) / m
        var = sum((v - mean) ** 2 for v in values) / (m - 1)
        rows.append(f"{line},{mean:.7g},{math.sqrt(var / m):.7g}")
    with open(args.out, "w") as f:
        f.write(header + ",illuminance_lux,std_error_lux\n")
        f.write("\n".join(rows) + "\n")
    info = {"sensors": len(sensors), "samples": args.samples, "pixels": k * k, "seed": args.seed,
            "setup_s": round(setup_s, 3), "bake_s": round(bake_s, 3), "total_s": round(time.time() - start, 3),
            "materials": report, "blender": bpy.app.version_string}
    if args.info:
        with open(args.info, "w") as f:
            json.dump(info, f, indent=1)
    print("cycles_irradiance: " + json.dumps({k: v for k, v in info.items() if k != "materials"}))


def scene_camera(scene, name, width, height):
    """The scene file's camera `name` (docs/scene-format.md: position, target, up, vertical fovDeg, near,
    far) as the Blender scene's camera, at width × height pixels."""
    cameras = {c.get("name"): c for c in scene.get("cameras", [])}
    if name not in cameras:
        fail(f"camera '{name}' not in the scene (cameras: {', '.join(map(str, cameras))})")
    c = cameras[name]
    position, target = to_blender(c["position"]), to_blender(c["target"])
    up = to_blender(c.get("up", [0, 1, 0]))
    forward = (target - position).normalized()
    right = forward.cross(up).normalized()
    true_up = right.cross(forward)
    data = bpy.data.cameras.new(name)
    data.sensor_fit = "VERTICAL"
    data.angle_y = math.radians(c.get("fovDeg", 50.0))
    data.clip_start = c.get("near", 0.1)
    data.clip_end = c.get("far", 1000.0)
    obj = bpy.data.objects.new("camera:" + name, data)
    # A Blender camera looks along its −Z with +Y up.
    obj.matrix_world = mathutils.Matrix.Translation(position) @ mathutils.Matrix(
        (right, true_up, -forward)).transposed().to_4x4()
    bpy.context.scene.collection.objects.link(obj)
    s = bpy.context.scene
    s.camera = obj
    s.render.resolution_x, s.render.resolution_y = width, height
    s.render.resolution_percentage = 100
    s.render.pixel_aspect_x = s.render.pixel_aspect_y = 1.0


def cmd_render(args):
    """Renders a scene camera; writes a multilayer EXR (Combined: radiance, cd/m²; IndexMA: each material's
    region number) and a JSON file naming the regions: pass_index k is the fly material of that name (the
    importer's copies, "Name.001", share their original's number)."""
    start = time.time()
    scene = load_scene_file(args.scene, fly_daylight=bool(args.sky))
    clear_blend()
    gltf_materials = import_models(scene, args.normals)
    add_scene_lights(scene, 0.0)
    report = setup_materials(scene, gltf_materials)
    configure_cycles(args.samples, args.seed, args.threads, scene.get("world", {}).get("skyRadianceCdM2", 0.0))
    sky = fly_sky_world(args.sky, args.sky_json) if args.sky else None
    scene_camera(scene, args.camera, args.width, args.height)
    names = sorted({gltf_materials[m.name]["flyName"] if m.name in gltf_materials else m.name
                    for m in bpy.data.materials if m.users > 0 and not m.name.startswith("fly-sensor")})
    regions = {name: k + 1 for k, name in enumerate(names)}
    for m in bpy.data.materials:
        name = gltf_materials[m.name]["flyName"] if m.name in gltf_materials else m.name
        if name in regions:
            m.pass_index = regions[name]
    s = bpy.context.scene
    s.view_layers[0].use_pass_material_index = True
    s.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    s.render.image_settings.color_depth = "32"
    s.render.image_settings.exr_codec = "ZIP"
    s.render.film_transparent = False
    s.render.filepath = os.path.abspath(args.out)
    s.render.use_file_extension = False
    setup_s = time.time() - start
    bpy.ops.render.render(write_still=True)
    render_s = time.time() - start - setup_s
    info = {"camera": args.camera, "width": args.width, "height": args.height, "samples": args.samples,
            "seed": args.seed, "regions": regions, "setup_s": round(setup_s, 3), "render_s": round(render_s, 3),
            "total_s": round(time.time() - start, 3), "sky": sky, "materials": report,
            "blender": bpy.app.version_string}
    with open(args.info, "w") as f:
        json.dump(info, f, indent=1)
    print("cycles_irradiance: " + json.dumps({k: v for k, v in info.items() if k not in ("materials", "regions")}))


def cmd_sensors(args):
    """Sensors on the scene's surfaces, found by casting rays down and sideways (±x, ±z in glTF space) from a
    lattice outside the scene's bounds; each sensor sits --offset metres off the hit surface and faces away
    from it (towards where the ray came from). Groups: the hit object's name and the direction faced."""
    scene = load_scene_file(args.scene)
    clear_blend()
    gltf_materials = import_models(scene, "geometric")
    add_scene_lights(scene, 0.0)
    bpy.context.view_layer.update()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    lo = [math.inf] * 3
    hi = [-math.inf] * 3
    for obj in bpy.data.objects:
        if obj.type != "MESH":
            continue
        for c in obj.bound_box:
            w = obj.matrix_world @ mathutils.Vector(c)
            for a in range(3):
                lo[a], hi[a] = min(lo[a], w[a]), max(hi[a], w[a])
    sun = next((o for o in bpy.data.objects if o.type == "LIGHT" and o.data.type == "SUN"), None)
    to_sun = (sun.matrix_world.to_quaternion() @ mathutils.Vector((0, 0, 1))) if sun else None
    if args.box:
        for a in (0, 1):
            lo[a], hi[a] = max(lo[a], -args.box), min(hi[a], args.box)
    size = max(hi[a] - lo[a] for a in range(3))
    spacing = args.spacing
    margin = 0.01 * size
    casts = []  # (origin, direction, facing name)
    # Blender axes: z up; glTF x = Blender x, glTF z = -Blender y.
    def lattice(a_axis, b_axis):
        na = int((hi[a_axis] - lo[a_axis]) / spacing)
        nb = int((hi[b_axis] - lo[b_axis]) / spacing)
        for ia in range(na + 1):
            for ib in range(nb + 1):
                yield (lo[a_axis] + (ia + 0.5 * (1 + (hi[a_axis] - lo[a_axis]) / spacing - na - 1)) * spacing,
                       lo[b_axis] + (ib + 0.5 * (1 + (hi[b_axis] - lo[b_axis]) / spacing - nb - 1)) * spacing)
    if args.origin:
        # Rays from one point in a Fibonacci lattice of directions over the sphere.
        origin = to_blender([float(c) for c in args.origin.split(",")])
        golden = math.pi * (3.0 - math.sqrt(5.0))
        for i in range(args.rays):
            z = 1.0 - 2.0 * (i + 0.5) / args.rays
            r = math.sqrt(1.0 - z * z)
            casts.append((origin, mathutils.Vector((r * math.cos(golden * i), r * math.sin(golden * i), z)),
                          None))
    else:
        for x, y in lattice(0, 1):
            casts.append((mathutils.Vector((x, y, hi[2] + margin)), mathutils.Vector((0, 0, -1)), "up"))
    if args.sideways:
        for y, z in lattice(1, 2):
            casts.append((mathutils.Vector((lo[0] - margin, y, z)), mathutils.Vector((1, 0, 0)), "side"))
            casts.append((mathutils.Vector((hi[0] + margin, y, z)), mathutils.Vector((-1, 0, 0)), "side"))
        for x, z in lattice(0, 2):
            casts.append((mathutils.Vector((x, lo[1] - margin, z)), mathutils.Vector((0, 1, 0)), "side"))
            casts.append((mathutils.Vector((x, hi[1] + margin, z)), mathutils.Vector((0, -1, 0)), "side"))
    rows = []
    for origin, direction, facing in casts:
        hit, location, normal, _, obj, _ = bpy.context.scene.ray_cast(depsgraph, origin, direction)
        if not hit:
            continue
        n = normal.normalized()
        if n.dot(direction) > 0:
            n = -n
        if facing is None:
            facing = "up" if n.z > 0.5 else "down" if n.z < -0.5 else "side"
        elif facing == "up" and n.z <= 0.5:
            continue  # a face steeper than 60°: left to the sideways casts
        if facing == "side" and abs(n.z) > 0.5:
            continue
        p = location + args.offset * n
        label = obj.name
        if len(label) > 4 and label[-4] == "." and label[-3:].isdigit():
            label = label[:-4]  # Blender's suffix for a repeated name
        group = label + "-" + facing
        if to_sun is not None:
            lit, *_ = bpy.context.scene.ray_cast(depsgraph, p + 1e-4 * n, to_sun)
            group += "-shadow" if lit or n.dot(to_sun) <= 0 else "-sunlit"
        pg, ng = to_gltf(p), to_gltf(n)
        rows.append(f"{pg[0]:.6f},{pg[1]:.6f},{pg[2]:.6f},{ng[0]:.6f},{ng[1]:.6f},{ng[2]:.6f},{group}")
    with open(args.out, "w") as f:
        f.write("x,y,z,nx,ny,nz,group\n" + "\n".join(rows) + "\n")
    print(f"cycles_irradiance: {len(rows)} sensors written to {args.out}")


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="cycles_irradiance.py")
    sub = ap.add_subparsers(dest="command", required=True)
    a = sub.add_parser("irradiance", help="irradiance (lux) at the sensors of a CSV file")
    a.add_argument("--scene", required=True)
    a.add_argument("--points", required=True)
    a.add_argument("--out", required=True)
    a.add_argument("--info", help="JSON file for the run's timings and the materials as converted")
    a.add_argument("--samples", type=int, default=256, help="Cycles samples per texel")
    a.add_argument("--pixels", type=int, default=4, help="texels per side of each sensor's block")
    a.add_argument("--seed", type=int, default=0)
    a.add_argument("--threads", type=int, default=0)
    a.add_argument("--quad-size", type=float, default=1e-4, help="sensor square's side, metres")
    a.add_argument("--normals", choices=("geometric", "shading"), default="shading")
    a.add_argument("--untextured", action="store_true",
                   help="ignore base-colour textures, vertex colours and alpha (a check of the rest)")
    a.add_argument("--sun-angle-deg", type=float, default=0.0, help="angular diameter of directional lights")
    s = sub.add_parser("sensors", help="place sensors on the scene's surfaces")
    s.add_argument("--scene", required=True)
    s.add_argument("--out", required=True)
    s.add_argument("--spacing", type=float, default=0.25, help="lattice spacing, metres")
    s.add_argument("--offset", type=float, default=2e-3, help="distance off the surface, metres")
    s.add_argument("--sideways", action="store_true", help="also cast along ±x and ±z")
    s.add_argument("--box", type=float, default=0.0, help="limit the lattice to |x|, |z| <= BOX (glTF axes)")
    s.add_argument("--from", dest="origin", help="instead of the lattice, cast from this point x,y,z (glTF)")
    s.add_argument("--rays", type=int, default=100, help="rays cast --from the point")
    r = sub.add_parser("render", help="render a scene camera with a material-index pass")
    r.add_argument("--scene", required=True)
    r.add_argument("--camera", required=True, help="the scene file's camera, by name")
    r.add_argument("--out", required=True, help="multilayer EXR: Combined (cd/m²) and IndexMA")
    r.add_argument("--info", required=True, help="JSON file: regions (material name → pass index), timings")
    r.add_argument("--width", type=int, default=320)
    r.add_argument("--height", type=int, default=180)
    r.add_argument("--samples", type=int, default=256, help="Cycles samples per pixel")
    r.add_argument("--seed", type=int, default=0)
    r.add_argument("--threads", type=int, default=0)
    r.add_argument("--normals", choices=("geometric", "shading"), default="shading")
    r.add_argument("--sky", help="fly's sky and sun as `fly sky --scene SCENE --out SKY.exr` writes them")
    r.add_argument("--sky-json", help="what `fly sky --json` printed for SKY.exr (the sun's position)")
    args = ap.parse_args(argv)
    if args.command == "irradiance":
        cmd_irradiance(args)
    elif args.command == "render":
        cmd_render(args)
    else:
        cmd_sensors(args)


main()
