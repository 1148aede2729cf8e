#!/usr/bin/env python3
"""Light maps between their points: random points on a baked scene's surfaces, and the comparison of what the
light maps give there (`fly probe`) with converged path tracing at the same points (`fly illuminance`).

  probe_check.py points BAKED --count 500 [--seed 1] [--box x0,y0,z0,x1,y1,z1] [--back] --out points.csv
      area-uniform random points on the front (--back: back) faces of BAKED/scene.gltf (world space), 1 mm off
      the surface along the face normal, in the sensor format both commands read.
  probe_check.py compare PROBE.csv REFERENCE.csv [--rel 0.05] [--k 3]
      the share of points where |probe − reference| <= k·σ_probe + rel·reference (σ_probe: the error the
      light maps report there), the worst points, and how the differences compare with the reported errors.
      Points whose converged reference is below --hidden-below lux (default 1) are counted apart: inside
      solids (a floor under a wall), or facing away from every light.
"""
import argparse
import base64
import csv
import json
import math
import os
import random
import struct
import sys

COMPONENT = {5120: ('b', 1), 5121: ('B', 1), 5122: ('h', 2), 5123: ('H', 2), 5125: ('I', 4), 5126: ('f', 4)}
COUNT = {'SCALAR': 1, 'VEC2': 2, 'VEC3': 3, 'VEC4': 4}


def accessor(gltf, buffers, index):
    a = gltf['accessors'][index]
    view = gltf['bufferViews'][a['bufferView']]
    fmt, size = COMPONENT[a['componentType']]
    n = COUNT[a['type']]
    stride = view.get('byteStride', size * n)
    data = buffers[view['buffer']]
    start = view.get('byteOffset', 0) + a.get('byteOffset', 0)
    out = []
    for i in range(a['count']):
        o = start + i * stride
        v = struct.unpack_from('<' + fmt * n, data, o)
        out.append(v if n > 1 else v[0])
    return out


def load(baked):
    path = os.path.join(baked, 'scene.gltf')
    gltf = json.load(open(path))
    buffers = []
    for b in gltf['buffers']:
        uri = b['uri']
        if uri.startswith('data:'):
            buffers.append(base64.b64decode(uri.split(',', 1)[1]))
        else:
            buffers.append(open(os.path.join(baked, uri), 'rb').read())
    triangles = []  # (a, b, c, name)
    for node in gltf.get('nodes', []):
        if 'mesh' not in node:
            continue
        mesh = gltf['meshes'][node['mesh']]
        for prim in mesh['primitives']:
            pos = accessor(gltf, buffers, prim['attributes']['POSITION'])
            idx = accessor(gltf, buffers, prim['indices']) if 'indices' in prim else list(range(len(pos)))
            for t in range(0, len(idx) - 2, 3):
                triangles.append((pos[idx[t]], pos[idx[t + 1]], pos[idx[t + 2]], mesh.get('name', '')))
    return triangles


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def points(args):
    box = [float(x) for x in args.box.split(',')] if args.box else None
    tris = []
    for a, b, c, name in load(args.baked):
        n = cross(sub(b, a), sub(c, a))
        area2 = math.sqrt(n[0] ** 2 + n[1] ** 2 + n[2] ** 2)
        if area2 <= 0:
            continue
        if box:
            centre = [(a[i] + b[i] + c[i]) / 3 for i in range(3)]
            if not all(box[i] <= centre[i] <= box[i + 3] for i in range(3)):
                continue
        sign = -1.0 if args.back else 1.0
        tris.append((a, b, c, name, tuple(sign * x / area2 for x in n), area2))
    total = sum(t[5] for t in tris)
    rng = random.Random(args.seed)
    cdf, s = [], 0.0
    for t in tris:
        s += t[5]
        cdf.append(s)
    with open(args.out + '.tmp', 'w', newline='') as f:
        w = csv.writer(f)
        w.writerow(['x', 'y', 'z', 'nx', 'ny', 'nz', 'name'])
        import bisect
        for k in range(args.count):
            a, b, c, name, n, _ = tris[min(len(tris) - 1, bisect.bisect_left(cdf, rng.random() * total))]
            r1, r2 = math.sqrt(rng.random()), rng.random()
            p = [a[i] * (1 - r1) + b[i] * r1 * (1 - r2) + c[i] * r1 * r2 + 1e-3 * n[i] for i in range(3)]
            w.writerow(['%.6f' % x for x in p] + ['%.6f' % x for x in n] + ['%s-%d' % (name or 'mesh', k)])
    os.replace(args.out + '.tmp', args.out)
    print('points: %d on %d triangles (%.1f m2) -> %s' % (args.count, len(tris), total / 2, args.out))


def compare(args):
    probe = list(csv.DictReader(open(args.probe)))
    ref = list(csv.DictReader(open(args.reference)))
    if len(probe) != len(ref):
        sys.exit('the two files have %d and %d rows' % (len(probe), len(ref)))
    ok, rows, z, hidden = 0, [], [], 0
    for p, r in zip(probe, ref):
        e, s = float(p['illuminance_lux']), float(p['std_error_lux'])
        e0, s0 = float(r['illuminance_lux']), float(r['std_error_lux'])
        if e0 < args.hidden_below:
            hidden += 1
            continue
        bound = args.k * s + args.rel * e0
        good = abs(e - e0) <= bound
        ok += good
        rows.append((abs(e - e0) / max(bound, 1e-9), p['name'], e, s, e0, s0))
        z.append((e - e0) / math.sqrt(s * s + s0 * s0) if s > 0 or s0 > 0 else 0.0)
    n = len(rows)
    az = sorted(abs(x) for x in z)
    # |z| of honest errors (z standard normal): median 0.67, 90th percentile 1.64.
    print('within %g sigma + %g %%: %d of %d (%.1f %%); |probe - reference| / sigma: median %.2f, 90th percentile '
          '%.2f (honest: 0.67, 1.64); %d below %g lx apart' % (args.k, 100 * args.rel, ok, n, 100.0 * ok / n,
                                                              az[n // 2], az[int(0.9 * n)], hidden, args.hidden_below))
    for q, name, e, s, e0, s0 in sorted(rows, reverse=True)[:args.worst]:
        print('  %-24s probe %10.1f +- %8.1f  reference %10.1f +- %7.1f  (%.2f of the bound)' % (name, e, s, e0, s0, q))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sp = ap.add_subparsers(dest='cmd', required=True)
    a = sp.add_parser('points')
    a.add_argument('baked')
    a.add_argument('--count', type=int, default=500)
    a.add_argument('--seed', type=int, default=1)
    a.add_argument('--box')
    a.add_argument('--back', action='store_true', help='on the back faces (two-sided surfaces seen from behind)')
    a.add_argument('--out', required=True)
    b = sp.add_parser('compare')
    b.add_argument('probe')
    b.add_argument('reference')
    b.add_argument('--rel', type=float, default=0.05)
    b.add_argument('--k', type=float, default=3.0)
    b.add_argument('--worst', type=int, default=8)
    b.add_argument('--hidden-below', type=float, default=1.0)
    args = ap.parse_args()
    points(args) if args.cmd == 'points' else compare(args)


if __name__ == '__main__':
    main()
