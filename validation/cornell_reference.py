#!/usr/bin/env python3
"""An independent path tracer for the cornell-box cases of validate.py: a third estimate, written apart from
both fly and Cycles, for sensors where the two disagree.

  validation/cornell_reference.py SENSORS.csv ROW [ROW ...] [--paths 500000] [--seed 1] [--two-sided-light]

SENSORS.csv is a case's sensors.csv (x,y,z,nx,ny,nz,...); ROW counts its data rows from 0. It prints each
sensor's illuminance (lux, Rec.709 luminance of the RGB estimate) with its standard error. Needs numpy
(Debian's python3-numpy, which Blender's glTF importer needs too) and $FLY_MODELS (validate.py).

The scene: Bevy's CornellBox.glb (34 triangles; node translations only), every material a double-sided
Lambertian reflector of the file's base colour, the emitter's emissiveFactor × emissiveStrength its radiance
(cd/m²) from its front face (the vertex normals' side, facing down), and with --two-sided-light from its back
face too; the validate.py cases' overrides in other words. The estimator: from the sensor, cosine-weighted
directions (E = π ∫ L cos θ dω / π); at the sensor and at every surface reached, next-event estimation of the
emitter by area (uniform over its triangles, with a shadow ray), and emission found by the path itself never
counted (so no weights to combine); Russian roulette from the third surface on with survival min(1, max
throughput); plain pseudo-random numbers (numpy's PCG64). Unbiased and simple, not fast: 500 000 paths take
about a minute.
"""
import argparse
import csv
import json
import os
import struct
import sys

import numpy as np

REC709_Y = np.array([0.2126, 0.7152, 0.0722])
EPS_M = 1e-3  # ray origins moved off surfaces (the box is 556 m wide)
BATCH = 20000


def read_glb(path):
    data = open(path, "rb").read()
    json_len = struct.unpack("<I", data[12:16])[0]
    doc = json.loads(data[20:20 + json_len])
    binary = data[20 + json_len + 8:]

    def accessor(i):
        a = doc["accessors"][i]
        view = doc["bufferViews"][a["bufferView"]]
        n = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
        fmt = {5126: "f", 5123: "H", 5125: "I", 5121: "B"}[a["componentType"]]
        size = struct.calcsize(fmt)
        offset = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        stride = view.get("byteStride", n * size)
        return np.array([struct.unpack_from("<" + fmt * n, binary, offset + k * stride)
                         for k in range(a["count"])], dtype=np.float64)

    return doc, accessor


class Scene:
    def __init__(self, path, two_sided_light):
        doc, accessor = read_glb(path)
        v0, v1, v2, albedo, emission, normal_hint = [], [], [], [], [], []
        for node in doc["nodes"]:
            if "mesh" not in node:
                continue
            if "rotation" in node or "scale" in node or "matrix" in node:
                raise SystemExit("cornell_reference: only translated nodes are supported")
            t = np.array(node.get("translation", [0, 0, 0]), dtype=np.float64)
            for prim in doc["meshes"][node["mesh"]]["primitives"]:
                mat = doc["materials"][prim["material"]]
                rho = mat.get("pbrMetallicRoughness", {}).get("baseColorFactor", [1, 1, 1, 1])[:3]
                strength = mat.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get(
                    "emissiveStrength", 1.0)
                le = [strength * c for c in mat.get("emissiveFactor", [0, 0, 0])]
                pos = accessor(prim["attributes"]["POSITION"]) + t
                nor = accessor(prim["attributes"]["NORMAL"])
                idx = accessor(prim["indices"]).astype(int).ravel()
                for k in range(0, len(idx), 3):
                    a, b, c = idx[k:k + 3]
                    v0.append(pos[a]), v1.append(pos[b]), v2.append(pos[c])
                    albedo.append(rho), emission.append(le)
                    normal_hint.append(nor[a] + nor[b] + nor[c])
        self.v0, self.v1, self.v2 = np.array(v0), np.array(v1), np.array(v2)
        self.e1, self.e2 = self.v1 - self.v0, self.v2 - self.v0
        ng = np.cross(self.e1, self.e2)
        self.area = 0.5 * np.linalg.norm(ng, axis=1)
        ng /= np.linalg.norm(ng, axis=1)[:, None]
        # The front face is the vertex normals' side (glTF: counter-clockwise; the same here).
        flip = np.einsum("tk,tk->t", ng, np.array(normal_hint)) < 0
        ng[flip] *= -1
        self.ng = ng
        self.albedo = np.array(albedo)
        self.emission = np.array(emission)
        self.two_sided_light = two_sided_light
        self.lights = np.where(self.emission.max(axis=1) > 0)[0]
        self.light_area = self.area[self.lights].sum()
        self.light_pmf = self.area[self.lights] / self.light_area

    def intersect(self, o, d):
        """Nearest hit of rays o + t d (Möller–Trumbore over all triangles): t (inf for none), triangle."""
        pv = np.cross(d[:, None, :], self.e2[None])
        det = np.einsum("ntk,tk->nt", pv, self.e1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = np.where(np.abs(det) > 1e-12, 1.0 / det, np.nan)
            tv = o[:, None, :] - self.v0[None]
            u = np.einsum("ntk,ntk->nt", tv, pv) * inv
            qv = np.cross(tv, self.e1[None])
            v = np.einsum("nk,ntk->nt", d, qv) * inv
            t = np.einsum("ntk,tk->nt", qv, self.e2) * inv
            ok = (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
        t = np.where(ok, t, np.inf)
        k = np.argmin(t, axis=1)
        return t[np.arange(len(o)), k], k

    def light_sample(self, p, n, rng):
        """Next-event estimate of the emitter at points p with normals n: Le cos θ cos θ' / d² / pdf_area,
        per channel (irradiance, lux)."""
        count = len(p)
        tri = self.lights[rng.choice(len(self.lights), count, p=self.light_pmf)]
        r1, r2 = np.sqrt(rng.random(count)), rng.random(count)
        y = (self.v0[tri] + self.e1[tri] * (r1 * (1 - r2))[:, None] + self.e2[tri] * (r1 * r2)[:, None])
        to = y - p
        dist = np.linalg.norm(to, axis=1)
        d = to / dist[:, None]
        cos = np.einsum("nk,nk->n", d, n)
        cos_light = -np.einsum("nk,nk->n", d, self.ng[tri])
        if self.two_sided_light:
            cos_light = np.abs(cos_light)
        value = np.where((cos > 0) & (cos_light > 0), cos * cos_light / dist ** 2 * self.light_area, 0.0)
        lit = np.where(value > 0)[0]
        if len(lit):
            t, _ = self.intersect(p[lit] + n[lit] * EPS_M, d[lit])
            value[lit[t < dist[lit] - 2 * EPS_M]] = 0.0
        return value[:, None] * self.emission[tri]


def onb(n):
    a = np.where(np.abs(n[:, :1]) > 0.9, np.array([[0.0, 1.0, 0.0]]), np.array([[1.0, 0.0, 0.0]]))
    t = np.cross(n, a)
    t /= np.linalg.norm(t, axis=1)[:, None]
    return t, np.cross(n, t)


def cosine_directions(n, rng):
    u1, u2 = rng.random(len(n)), rng.random(len(n))
    r, phi = np.sqrt(u1), 2 * np.pi * u2
    t, s = onb(n)
    return t * (r * np.cos(phi))[:, None] + s * (r * np.sin(phi))[:, None] + n * np.sqrt(1 - u1)[:, None]


def paths(scene, p, n, count, rng):
    """count independent estimates of the irradiance at p facing n (RGB, lux)."""
    p = np.repeat(p[None], count, 0)
    n = np.repeat(n[None], count, 0)
    total = scene.light_sample(p, n, rng)
    beta = np.ones((count, 3))
    alive = np.arange(count)
    o, d = p + n * EPS_M, cosine_directions(n, rng)
    bounces = 0
    while len(alive):
        t, k = scene.intersect(o, d)
        hit = np.isfinite(t)
        alive, o, d, t, k, beta = alive[hit], o[hit], d[hit], t[hit], k[hit], beta[hit]
        x = o + d * t[:, None]
        front = np.einsum("nk,nk->n", scene.ng[k], d) < 0
        # The one-sided emitter's back face neither emits nor reflects.
        black = (scene.emission[k].max(axis=1) > 0) & ~front & (not scene.two_sided_light)
        keep = ~black
        alive, x, k, beta, front = alive[keep], x[keep], k[keep], beta[keep], front[keep]
        side = np.where(front[:, None], scene.ng[k], -scene.ng[k])
        # Reflected radiance ρ/π · E, seen over the sensor's cosine kernel: π · β · ρ/π · E = β ρ E.
        beta = beta * scene.albedo[k]
        total[alive] += beta * scene.light_sample(x, side, rng)
        bounces += 1
        if bounces >= 3:
            q = np.minimum(1.0, beta.max(axis=1))
            survive = rng.random(len(q)) < q
            alive, x, beta, side = alive[survive], x[survive], beta[survive] / q[survive][:, None], side[survive]
        o, d = x + side * EPS_M, cosine_directions(side, rng)
    return total


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("sensors")
    ap.add_argument("rows", type=int, nargs="+")
    ap.add_argument("--paths", type=int, default=500000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--two-sided-light", action="store_true")
    args = ap.parse_args()
    base = os.environ.get("FLY_MODELS")
    if not base:
        raise SystemExit("cornell_reference: set FLY_MODELS (see validate.py)")
    scene = Scene(os.path.join(base, "bevy/CornellBox/CornellBox.glb"), args.two_sided_light)
    with open(args.sensors) as f:
        rows = list(csv.DictReader(f))
    rng = np.random.default_rng(args.seed)
    print("row,x,y,z,nx,ny,nz,illuminance_lux,std_error_lux,paths")
    for row in args.rows:
        if not 0 <= row < len(rows):
            raise SystemExit(f"cornell_reference: {args.sensors} has no row {row}")
        r = rows[row]
        p = np.array([float(r[c]) for c in ("x", "y", "z")])
        n = np.array([float(r[c]) for c in ("nx", "ny", "nz")])
        n /= np.linalg.norm(n)
        values = np.concatenate([paths(scene, p, n, min(BATCH, args.paths - done), rng) @ REC709_Y
                                 for done in range(0, args.paths, BATCH)])
        print(f"{row},{r['x']},{r['y']},{r['z']},{r['nx']},{r['ny']},{r['nz']},{values.mean():.6g},"
              f"{values.std(ddof=1) / np.sqrt(len(values)):.4g},{len(values)}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
