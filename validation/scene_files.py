"""Small glTF 2.0 and PNG writers (standard library only) for the validation's analytic scenes, and the
Lambertian form of a fly scene file."""
import json
import math
import os
import struct
import zlib


def write_png_rgba(path, width, height, pixel):
    """8-bit RGBA PNG; pixel(x, y) -> (r, g, b, a) in 0..255 (PNG spec, ISO/IEC 15948)."""
    raw = bytearray()
    for y in range(height):
        raw.append(0)  # filter type None
        for x in range(width):
            raw.extend(pixel(x, y))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(bytes(raw), 9)))
        f.write(chunk(b"IEND", b""))


def write_gltf(path, meshes, materials, images=(), filter_mode=9729):
    """meshes: [{name, triangles: [((x,y,z),(x,y,z),(x,y,z)), ...], uvs: optional per-corner (u,v) list,
    material: index}], each drawn once at the origin; triangles wind counter-clockwise seen from the front,
    and every corner gets the triangle's flat normal. materials: glTF material dicts. images: PNG file
    names beside the glTF (texture i uses image i), sampled with filter_mode (glTF magFilter and minFilter:
    9729 LINEAR, 9728 NEAREST) and REPEAT. The buffer is a .bin file beside the glTF (a data URI would cost
    both programs base64 decoding at start-up, which a real model does not)."""
    blob = bytearray()
    bin_path = os.path.splitext(path)[0] + ".bin"
    views, accessors, gltf_meshes, nodes = [], [], [], []

    def add_view(data, target):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob.extend(data)
        return len(views) - 1

    for mesh in meshes:
        pos, nrm, uv = bytearray(), bytearray(), bytearray()
        lo, hi = [math.inf] * 3, [-math.inf] * 3
        for t, tri in enumerate(mesh["triangles"]):
            a, b, c = tri
            e1 = [b[i] - a[i] for i in range(3)]
            e2 = [c[i] - a[i] for i in range(3)]
            n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
            ln = math.sqrt(sum(x * x for x in n))
            n = [x / ln for x in n]
            for k, p in enumerate(tri):
                pos += struct.pack("<3f", *p)
                nrm += struct.pack("<3f", *n)
                for i in range(3):
                    lo[i], hi[i] = min(lo[i], p[i]), max(hi[i], p[i])
                if "uvs" in mesh:
                    uv += struct.pack("<2f", *mesh["uvs"][3 * t + k])
        count = 3 * len(mesh["triangles"])
        attributes = {}
        accessors.append({"bufferView": add_view(pos, 34962), "componentType": 5126, "count": count,
                          "type": "VEC3", "min": [float(struct.unpack("<f", struct.pack("<f", x))[0]) for x in lo],
                          "max": [float(struct.unpack("<f", struct.pack("<f", x))[0]) for x in hi]})
        attributes["POSITION"] = len(accessors) - 1
        accessors.append({"bufferView": add_view(nrm, 34962), "componentType": 5126, "count": count,
                          "type": "VEC3"})
        attributes["NORMAL"] = len(accessors) - 1
        if uv:
            accessors.append({"bufferView": add_view(uv, 34962), "componentType": 5126, "count": count,
                              "type": "VEC2"})
            attributes["TEXCOORD_0"] = len(accessors) - 1
        gltf_meshes.append({"name": mesh["name"],
                            "primitives": [{"attributes": attributes, "material": mesh["material"]}]})
        nodes.append({"name": mesh["name"], "mesh": len(gltf_meshes) - 1})
    doc = {
        "asset": {"version": "2.0", "generator": "fly validation/scene_files.py"},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": gltf_meshes,
        "materials": materials,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob), "uri": os.path.basename(bin_path)}],
    }
    if images:
        doc["images"] = [{"uri": name} for name in images]
        doc["samplers"] = [{"magFilter": filter_mode, "minFilter": filter_mode, "wrapS": 10497, "wrapT": 10497}]
        doc["textures"] = [{"source": i, "sampler": 0} for i in range(len(images))]
    with open(bin_path, "wb") as f:
        f.write(bytes(blob))
    with open(path, "w") as f:
        json.dump(doc, f)


def quad(centre, half_u, half_v, u_axis, v_axis):
    """Two triangles of the rectangle centre ± half_u u_axis ± half_v v_axis, front face along u × v."""
    def corner(su, sv):
        return tuple(centre[i] + su * half_u * u_axis[i] + sv * half_v * v_axis[i] for i in range(3))
    a, b, c, d = corner(-1, -1), corner(1, -1), corner(1, 1), corner(-1, 1)
    return [(a, b, c), (a, c, d)], [(0, 0), (1, 0), (1, 1), (0, 0), (1, 1), (0, 1)]


def sphere_inward(radius, segments, rings):
    """A UV sphere whose vertices lie on the radius, its triangles' front faces towards the centre."""
    def point(i, j):
        theta = math.pi * j / rings
        phi = 2 * math.pi * i / segments
        return (radius * math.sin(theta) * math.cos(phi), radius * math.cos(theta),
                radius * math.sin(theta) * math.sin(phi))
    tris = []
    for j in range(rings):
        for i in range(segments):
            a, b = point(i, j), point(i + 1, j)
            c, d = point(i + 1, j + 1), point(i, j + 1)
            # a, b, c winds counter-clockwise seen from outside (b − a along φ, c − a along φ and θ):
            # the reverse faces the centre.
            if j != 0:
                tris.append((a, c, b))
            if j != rings - 1:
                tris.append((a, d, c))
    return tris


def gltf_json(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == b"glTF":
        length = struct.unpack("<I", data[12:16])[0]
        return json.loads(data[20:20 + length].decode("utf-8"))
    return json.loads(data.decode("utf-8-sig"))


def lambertian_overrides(scene, base_dir):
    """Overrides that make every material of the scene's models Lambertian with diffuse albedo = base colour
    factor (× base-colour texture, which fly keeps under an override): no reflection, no transmission, no
    bump. One override per material name; names shared by several models get the first model's factor."""
    overrides, seen = [], set()
    for model in scene.get("models", []):
        path = model["file"] if os.path.isabs(model["file"]) else os.path.join(base_dir, model["file"])
        doc = gltf_json(path)
        used = {p["material"] for mesh in doc.get("meshes", []) for p in mesh.get("primitives", [])
                if "material" in p}
        for i, m in enumerate(doc.get("materials", [])):
            name = model.get("namePrefix", "") + m.get("name", f"material {i}")
            if name in seen or "name" not in m or i not in used:
                continue  # materials only KHR_materials_variants names are not in fly's scene
            seen.add(name)
            factor = m.get("pbrMetallicRoughness", {}).get("baseColorFactor", [1, 1, 1, 1])
            o = {"material": name, "diffuse": [round(c, 7) for c in factor[:3]],
                 "reflection": [0, 0, 0], "transmission": [0, 0, 0]}
            if "normalTexture" in m:
                o["bumpScale"] = 0
            overrides.append(o)
    return overrides
