#!/usr/bin/env python3
"""Prints the README's Performance table (Markdown) from bench/results/*.json.

Usage: python3 bench/perf_table.py [bench/results]
Each row: the case, Pliant's figure, the baseline's figure, and their ratio,
all measured side by side in one run of one benchmark program.
"""
import json
import pathlib
import sys


def smoke_sim_rows(d):
    rows = []
    fwd = {}
    for c in d["cases"]:
        name = c["case"]
        if name.startswith("pressure_"):
            m, j = c["mgpcg"], c["jacobi_pcg"]
            rows.append((
                f"Pressure solve {name[len('pressure_'):]} ({c['cells']} cells, tol {c['tolerance']:g}, "
                f"{c['threads']} thread)",
                f"MGPCG: {m['iterations']} it, {m['time_s'] * 1e3:.2f} ms",
                f"Jacobi-PCG: {j['iterations']} it, {j['time_s'] * 1e3:.1f} ms",
                f"{c['time_ratio_jacobi_over_mgpcg']:.1f}x faster"))
        elif name.startswith("forward_") and "thread_scaling" not in name:
            fwd.setdefault(name, {})[c["threads"]] = c
    for name, by_threads in fwd.items():
        one = by_threads.get(1)
        for t, c in sorted(by_threads.items()):
            label = f"Forward {name[len('forward_'):]} ({int(c['cells'])} cells), {t} thread(s)"
            pl = f"{c['cell_steps_per_s'] / 1e6:.2f} M cell-steps/s ({c['ms_per_step']:.1f} ms/step)"
            if t == 1 or one is None:
                rows.append((label, pl, "-", "-"))
            else:
                rows.append((label, pl, f"1 thread: {one['cell_steps_per_s'] / 1e6:.2f} M",
                             f"{c['cell_steps_per_s'] / one['cell_steps_per_s']:.2f}x"))
    return rows


def smoke_control_rows(cases):
    rows = []
    for c in cases:
        g = "x".join(str(n) for n in c["grid"] if n > 1)
        rows.append((
            f"Keyframe control {c['case'].removesuffix('.json')} ({g} x {c['frames']}): "
            f"time to the same objective",
            f"ADMM: {c['pliant_s']:.2f} s (IoU min {c['iou_min']:.2f})",
            f"L-BFGS: {c['lbfgs_s']:.2f} s",
            f"{c['speedup']:.2f}x"))
    return rows


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "bench/results")
    print("| case | Pliant | baseline | ratio |")
    print("|---|---|---|---|")
    for path in sorted(root.glob("*.json")):
        d = json.loads(path.read_text())
        if isinstance(d, list) and d and "lbfgs_s" in d[0]:
            for r in smoke_control_rows(d):
                print("| " + " | ".join(r) + " |")
            print(f"\n{path.stem}: `build/bin/bench_smoke_control` (issue 3, open).\n")
        elif isinstance(d, dict) and d.get("bench") == "smoke_sim":
            for r in smoke_sim_rows(d):
                print("| " + " | ".join(r) + " |")
            m = d.get("machine", {})
            print(f"\nsmoke_sim: {d.get('mode')} mode, {m.get('nproc')} x {m.get('cpu')}, "
                  f"OMP_WAIT_POLICY={m.get('omp_wait_policy')}, load average at start "
                  f"{m.get('load_average_at_start')} (`build/bin/bench_smoke_sim`).\n")


if __name__ == "__main__":
    main()
