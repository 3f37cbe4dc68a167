"""Writes a wavy torus of N x M quads (every vertex of valence 4) as OBJ:
python3 wavy_torus.py N M out.obj"""
import math, sys
N, M, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
R, r = 3.0, 1.0
with open(out, "w") as f:
    for i in range(N):
        u = 2 * math.pi * i / N
        for j in range(M):
            v = 2 * math.pi * j / M
            rr = r * (1 + 0.15 * math.sin(5 * u) * math.cos(3 * v))
            x = (R + rr * math.cos(v)) * math.cos(u)
            y = (R + rr * math.cos(v)) * math.sin(u)
            f.write(f"v {x:.6f} {y:.6f} {rr * math.sin(v):.6f}\n")
    for i in range(N):
        for j in range(M):
            a, b = i * M + j + 1, (i + 1) % N * M + j + 1
            c, d = (i + 1) % N * M + (j + 1) % M + 1, i * M + (j + 1) % M + 1
            f.write(f"f {a} {b} {c} {d}\n")
