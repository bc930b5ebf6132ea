#!/usr/bin/env python3
"""Where pbad3's energy loss on the 10-link chain comes from (eighteenth session).

Computes the planar small-oscillation modes of assets/models/chain10.xml (uniform
capsule links, absolute angles, generalized eigenproblem K v = w^2 M v by Cholesky and
Jacobi), releases the chain from rest in one mode shape (largest link angle 0.05 rad)
with `pliant run`, tabulates the take with `pliant export --format csv` and prints the
share of the swing energy (E0 - E at hanging rest) lost in 10 s for dt 0.05, 0.025,
0.0125. The stencil's linear theory loses 0.96 (w dt)^4 of a mode's energy per step.

    python3 bench/articulated/chain_mode_damping.py [--pliant build/bin/pliant] [--integrator pbad3]
"""
import argparse, csv, json, math, os, subprocess, tempfile

ap = argparse.ArgumentParser()
ap.add_argument("--pliant", default=os.path.join(os.path.dirname(__file__), "../../build/bin/pliant"))
ap.add_argument("--integrator", default="pbad3")
ap.add_argument("--modes", default="0,1,3")
args = ap.parse_args()
repo = os.path.abspath(os.path.join(os.path.dirname(__file__), "../.."))
n, l, r, g = 10, 0.1, 0.01, 9.81
m = 1000 * (math.pi * r * r * l + 4 / 3 * math.pi * r ** 3)  # capsule of density 1000

# Linearized about hanging: link k's centre moves by sum_{j<k} l phi_j + l/2 phi_k.
A = [[l if j < k else (l / 2 if j == k else 0) for j in range(n)] for k in range(n)]
M = [[m * sum(A[k][i] * A[k][j] for k in range(n)) + (m * l * l / 12 if i == j else 0) for j in range(n)]
     for i in range(n)]
K = [[m * g * l * (n - 1 - i + 0.5) if i == j else 0 for j in range(n)] for i in range(n)]
L = [[0.0] * n for _ in range(n)]
for i in range(n):
    for j in range(i + 1):
        s = M[i][j] - sum(L[i][k] * L[j][k] for k in range(j))
        L[i][j] = math.sqrt(s) if i == j else s / L[j][j]
Li = [[0.0] * n for _ in range(n)]  # L^-1 by forward substitution, column by column
for c in range(n):
    for i in range(n):
        Li[i][c] = ((1.0 if i == c else 0.0) - sum(L[i][k] * Li[k][c] for k in range(i))) / L[i][i]
C = [[sum(Li[i][a] * K[a][a] * Li[j][a] for a in range(n)) for j in range(n)] for i in range(n)]
V = [[1.0 if i == j else 0.0 for j in range(n)] for i in range(n)]
for _ in range(100):
    if sum(C[i][j] ** 2 for i in range(n) for j in range(n) if i != j) < 1e-24:
        break
    for p in range(n):
        for q in range(p + 1, n):
            th = 0.5 * math.atan2(2 * C[p][q], C[q][q] - C[p][p])
            c, s = math.cos(th), math.sin(th)
            for k in range(n):
                C[k][p], C[k][q] = c * C[k][p] - s * C[k][q], s * C[k][p] + c * C[k][q]
            for k in range(n):
                C[p][k], C[q][k] = c * C[p][k] - s * C[q][k], s * C[p][k] + c * C[q][k]
            for k in range(n):
                V[k][p], V[k][q] = c * V[k][p] - s * V[k][q], s * V[k][p] + c * V[k][q]
w = [math.sqrt(C[i][i]) for i in range(n)]
order = sorted(range(n), key=lambda i: w[i])
print("planar mode frequencies (rad/s):", " ".join("%.1f" % w[i] for i in order))

tmp = tempfile.mkdtemp(prefix="chain_modes_")
def energies(qpos, dt, duration):
    scene = {"pliant": 1, "kind": "articulated", "model": repo + "/assets/models/chain10.xml",
             "integrator": args.integrator, "dt": dt, "duration_s": duration,
             "initial": {"qpos": qpos, "qvel": [0] * 2 * n}}
    path = os.path.join(tmp, "scene.json")
    json.dump(scene, open(path, "w"))
    subprocess.run([args.pliant, "run", path, "--take", tmp + "/take"], check=True, capture_output=True)
    subprocess.run([args.pliant, "export", tmp + "/take", "--format", "csv", "--out", tmp + "/csv"],
                   check=True, capture_output=True)
    return [float(row["energy[2]"]) for row in csv.DictReader(open(tmp + "/csv/frames.csv"))]

for mi in [int(x) for x in args.modes.split(",")]:
    u = [V[k][order[mi]] for k in range(n)]
    phi = [0.0] * n  # phi = L^-T u
    for i in reversed(range(n)):
        phi[i] = (u[i] - sum(L[k][i] * phi[k] for k in range(i + 1, n))) / L[i][i]
    scale = 0.05 / max(abs(x) for x in phi)
    theta = [scale * (phi[k] - (phi[k - 1] if k else 0)) for k in range(n)]  # hinge angles are relative
    qpos = [0.0] * 2 * n
    for k in range(n):
        qpos[2 * k] = (math.pi / 2 if k == 0 else 0) + theta[k]  # j{k}y; pi/2 hangs link 0
    for dt in (0.05, 0.025, 0.0125):
        E = energies(qpos, dt, 10)
        rest = energies([math.pi / 2] + [0] * (2 * n - 1), dt, dt)[0]
        wh = w[order[mi]] * dt
        theory = 1 - (1 - min(1.0, 0.96 * wh ** 4)) ** round(10 / dt)
        print("mode %d (w %.1f rad/s) dt %.4f (w dt %.3f): swing energy lost in 10 s %.4f (pbad3 stencil's linear theory %.4f)"
              % (mi, w[order[mi]], dt, wh, (E[0] - E[-1]) / (E[0] - rest), theory))
