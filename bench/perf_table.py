#!/usr/bin/env python3
"""Prints the README's Performance table (Markdown) from bench/results/*.json.

Usage: python3 bench/perf_table.py [bench/results]
Each row: the case, Pliant's figure, the baseline's figure, and their ratio,
all measured side by side in one run of one benchmark program.
"""
import json
import re
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
    # Converged comparisons (both solvers to Pliant's end objective E*) first; the
    # per-iteration A/B rows ("nso_skip_gap=" in the case) are not speedups: left out.
    cases = [c for c in cases if "nso_skip_gap=" not in c["case"]]
    cases.sort(key=lambda c: c.get("comparison") != "converged")
    rows = []
    for c in cases:
        g = "x".join(str(n) for n in c["grid"] if n > 1)
        if c.get("comparison") == "pliant_only":
            rows.append((f"Keyframe control {c['case'].split('.json')[0]} ({g} x {c['frames']}), `pliant run` as shipped",
                         f"Pliant: {c['pliant_s'] / 60:.1f} CPU min, IoU min {c['iou_min']:.2f}, {c['peak_mb'] / 1024:.1f} GB",
                         "target < 30 min (dissertation ~7 h); no L-BFGS run at this size", f"{1800 / c['pliant_s']:.1f}x under"))
            continue
        if c.get("comparison") == "before_after":  # the same shipped scene, previous code vs this code
            rows.append((f"Keyframe control {c['case']}: CPU s on one thread",
                         f"now: {c['after_cpu_s']:.1f} s (E {c['after_objective']:.1f})",
                         f"before: {c['before_cpu_s']:.1f} s (E {c['before_objective']:.1f})",
                         (f"{c['before_cpu_s'] / c['after_cpu_s']:.2f}x faster"
                          if c['after_cpu_s'] <= c['before_cpu_s'] else
                          f"{c['after_cpu_s'] / c['before_cpu_s']:.2f}x slower")))
            continue
        if c.get("comparison") == "evaluation_profile":  # one objective + gradient, 1 vs 2 threads
            if "after_2thread_wall_s" in c and "after_1thread_wall_s" in c:
                rows.append((f"Keyframe control {c['case']}: wall s, 2 threads vs 1 (quiet moment)",
                             f"2 threads: {c['after_2thread_wall_s']:.2f} s",
                             f"1 thread: {c['after_1thread_wall_s']:.2f} s",
                             f"{c['after_1thread_wall_s'] / c['after_2thread_wall_s']:.2f}x"))
            continue
        if c.get("comparison") == "converged" and c.get("baseline") == "none":  # Pliant alone
            name = c["case"].split(" converged")[0].removesuffix(".json").replace(".json", "")
            rows.append((f"Keyframe control {name} ({g} x {c['frames']}), converged, Pliant only",
                         f"Pliant: {c['pliant_s']:.1f} s CPU, E* {c['pliant_objective']:.1f} "
                         f"(IoU min {c['iou_min']:.2f})", "no L-BFGS run", "-"))
            continue
        if c.get("comparison") == "converged":
            ratio = (f">= {c['speedup']:.2f}x" if c.get("speedup_is_lower_bound") else f"{c['speedup']:.2f}x")
            name = c["case"].split(" converged")[0].removesuffix(".json").replace(".json", "")
            rows.append((
                f"Keyframe control {name} ({g} x {c['frames']}), converged: CPU s to Pliant's end objective",
                f"Pliant: {c['pliant_s']:.1f} s (IoU min {c['iou_min']:.2f})",
                f"{c['baseline']}: {c['lbfgs_s']:.1f} s" +
                ("" if c.get("lbfgs_reached") else
                 f" (stalled at E {c['lbfgs_best_objective']:.1f} > Pliant's {c['pliant_objective']:.1f}: "
                 f"{c.get('lbfgs_stop_reason')} after {c.get('lbfgs_restarts', 0)} restarts)"
                 if "lbfgs_best_objective" in c and "pliant_objective" in c else
                 f" (stopped: {c.get('lbfgs_stop_reason')})") +
                (f" (IoU min {c['lbfgs_iou_min']:.2f})" if "lbfgs_iou_min" in c else ""),
                ratio))
            continue
        if c.get("lbfgs_stalled") or (c.get("speedup_is_lower_bound") and c["speedup"] < 0.01):
            ratio = "L-BFGS never gets there"
        elif c.get("speedup_is_lower_bound"):
            ratio = f">= {c['speedup']:.2f}x"
        else:
            ratio = f"{c['speedup']:.2f}x"
        rows.append((
            f"Keyframe control {c['case'].removesuffix('.json')} ({g} x {c['frames']}): "
            f"time to the same re-simulated objective (fixed budgets; L-BFGS in 20-iteration chunks; "
            f"{re.sub(r'^[0-9-]+ ', '', str(c.get('session', 'earlier')).split(':')[0].split(' (')[0])} session's code and scenes)",
            f"ADMM: {c['pliant_s']:.1f} s (IoU min {c['iou_min']:.2f})",
            f"L-BFGS: {c['lbfgs_s']:.1f} s" + (f" (IoU min {c['lbfgs_iou_min']:.2f})" if "lbfgs_iou_min" in c else ""),
            ratio))
    return rows


def articulated_rows(cases):
    rows = []
    for c in cases:
        name = c["case"]
        if name.startswith("matched") and "ratio_vs_mujoco" in c:
            basis = "CPU" if "CPU" in c.get("timing", "") else "wall"
            rows.append((
                f"PBAD {name} {c['links']} links, 1% energy drift: {basis} s per simulated s",
                f"{c['pliant_method']} dt {c['pliant_dt']:g}: {c['pliant_wall_per_sim_s'] * 1e3:.3f} ms",
                f"{c['mujoco_method']} dt {c['mujoco_dt']:g}: {c['mujoco_wall_per_sim_s'] * 1e3:.3f} ms",
                f"{c['ratio_vs_mujoco']:.2f} (Pliant / MuJoCo; < 1 is faster)"))
        elif name.startswith("matched"):
            rows.append((f"PBAD {name} {c['links']} links, 1% energy drift", c.get("pliant_method", "-"),
                         c.get("mujoco_method", "-"), "-"))
    creep = {c["method"]: c for c in cases if c["case"] == "slope_creep"}
    if "pbad3" in creep and "mujoco_euler" in creep:
        p, m = creep["pbad3"], creep["mujoco_euler"]
        rows.append(("Box on a 20 degree slope, mu 0.5, 5 s: creep", f"pbad3: {p['creep_m'] * 1e3:.3f} mm",
                     f"mujoco_euler: {m['creep_m'] * 1e3:.2f} mm", f"{m['creep_m'] / p['creep_m']:.0f}x less"))
    batch = {c["threads"]: c for c in cases if c["case"] == "batched_rollouts"}
    if batch:
        t = max(batch)
        c = batch[t]
        rows.append((f"Batched rollouts: {c['trajectories']} x {c['links']} links x {c['steps']} steps",
                     f"{t} threads: {c['wall_s']:.2f} s", f"1 thread: {batch.get(1, c)['wall_s']:.2f} s",
                     f"{batch.get(1, c)['wall_s'] / c['wall_s']:.2f}x"))
    return rows


def liquid_rows(cases):
    rows = []
    for c in cases:
        if c["case"].startswith("sim_") or c["case"].startswith("dam_break"):
            extra = f", {c['wall_per_sim_s']:.1f} wall-s per sim-s" if "wall_per_sim_s" in c else ""
            rows.append((f"Liquid {c['case']} ({c['particles']} particles, {c.get('threads', '-')} thread(s))",
                         f"{c['particle_steps_per_s'] / 1e6:.2f} M particle-steps/s{extra}",
                         "SPlisHSPlasH DFSPH (issue's figure, 2 cores): 0.9 M/s, 32 wall-s per sim-s",
                         f"{c['particle_steps_per_s'] / 0.9e6:.2f}x"))
        elif c["case"].startswith("planner_"):
            n = len(c.get("per_problem", []))
            rows.append((f"Liquid {c['case']} on {n} held-out problems",
                         f"success@5% {c['success_at_5']:.2f}, mean transfer {c['mean_transfer']:.3f}, "
                         f"{c['plan_s']:.1f} s per plan",
                         "dissertation (feedback planner): < 5% spilled on 90% of problems", "-"))
    return rows


# Bench variant rows `optimize_<scene>_lbfgs_<line search>_m<memory>_r<restarts>_...`
# (LBFGS_VARIANTS): the fastest to 1% is the fairest L-BFGS to compare against.
LBFGS_VARIANT = re.compile(r"_lbfgs_(armijo|wolfe|strong_wolfe|bracketing|nocedal_wright)_m\d+_r\d+_")


def strongest_lbfgs(cases, base):
    best = None
    for c in cases:
        name = c["case"]
        if name.startswith(base + "_lbfgs_") and LBFGS_VARIANT.search(name[len(base):]):
            t = c.get("time_to_1pct_cpu_s")
            if t and (best is None or t < best[1]):
                best = (name[len(base) + len("_lbfgs_"):], t)
    return best


def soft_rows(cases):
    rows = []
    by = {c["case"]: c for c in cases}
    for c in cases:
        name = c["case"]
        if name.startswith("reduced_vs_full"):
            basis = c.get("basis", "linear")
            rows.append((f"Soft reduced vs full FEM, {basis} basis, {c['modes']} modes ({c['lattice_nodes']} nodes)",
                         f"error {c['relative_error'] * 100:.1f}%, {c['reduced_wall_s']:.2f} s",
                         f"full FEM {c['full_wall_s']:.2f} s", f"{c['speedup']:.1f}x"))
        elif name.startswith("playback_"):
            # Frames per CPU second where measured (the machine is shared; OMP_NUM_THREADS=1).
            fps = c.get("playback_fps_cpu", c["playback_fps"])
            unit = "frames per CPU s" if "playback_fps_cpu" in c else "fps"
            rows.append((f"Soft realtime playback {name[len('playback_'):].replace('_rotation_strain', ', rotation-strain coordinates')}",
                         f"{fps:.0f} {unit}", "target 200 fps", f"{fps / 200:.1f}x"))
        elif name.endswith("_hybrid"):
            # CPU seconds to 1% of the initial objective (the machine is shared).
            base = name[: -len("_hybrid")]
            lb = by.get(base + "_lbfgs", {})
            hy_t, lb_t = c.get("time_to_1pct_cpu_s"), lb.get("time_to_1pct_cpu_s")
            common = lb.get("hybrid_vs_lbfgs_common_cpu") or lb.get("hybrid_vs_lbfgs_common_cpu_at_least")
            at_least = "" if lb.get("hybrid_vs_lbfgs_common_cpu") else ">= "
            if hy_t and lb_t:
                ratio = f"{lb_t / hy_t:.2f}x"
            elif hy_t:
                ratio = f"L-BFGS never reaches 1% (stops at x{lb.get('final_over_initial', float('nan')):.2f})"
            elif common and c.get("time_to_common_cpu_s"):
                # Neither reaches 1%: CPU s to 1.1 x the best final objective of the run.
                ratio = (f"neither reaches 1%; to x{c['common_level'] / c['objective_initial']:.3f} "
                         f"(1.1 x best final): {at_least}{common:.1f}x")
            else:
                ratio = "neither reaches 1%"
            rows.append((f"Soft {base[len('optimize_'):]}: CPU s to 1% of the initial objective",
                         f"hybrid: {c['iterations']} it, objective x{c['final_over_initial']:.3f}"
                         + (f", 1% in {hy_t:.1f} s" if hy_t else "") + f", {c['distance_per_s']:.3f} m/s",
                         f"L-BFGS: objective x{lb.get('final_over_initial', float('nan')):.3f}"
                         + (f", 1% in {lb_t:.1f} s" if lb_t else ""),
                         ratio))
            strongest = strongest_lbfgs(cases, base)
            if strongest:
                v, lb_t = strongest
                rows.append((f"Soft {base[len('optimize_'):]}: CPU s to 1%, hybrid vs the strongest L-BFGS variant",
                             f"hybrid: 1% in {hy_t:.1f} s" if hy_t else "hybrid: never reaches 1%",
                             f"L-BFGS {v}: 1% in {lb_t:.1f} s",
                             f"{lb_t / hy_t:.2f}x" if hy_t else "L-BFGS wins"))
        elif name.endswith("_spacetime"):
            base = name[: -len("_spacetime")]
            hy = by.get(base + "_hybrid", {})
            rows.append((f"Soft {base[len('optimize_'):]}: spacetime optimizer vs hybrid shooting (re-simulated)",
                         f"spacetime: {c['iterations']} it, objective x{c['final_over_initial']:.3f}, {c['cpu_s']:.1f} s",
                         f"hybrid: objective x{hy.get('final_over_initial', float('nan')):.3f}, "
                         f"{hy.get('cpu_s', float('nan')):.1f} s",
                         f"{c['spacetime_over_best_shooting']:.2f} (objective / best shooting; < 1 wins)"
                         if c.get("spacetime_over_best_shooting") else "-"))
    return rows


def editor_rows(cases):
    rows = []
    for c in cases:
        fp = c["first_preview_s"]
        rows.append((f"Editor while solving {c['case']}",
                     f"{c['ui_fps_while_solving']:.1f} fps, first preview "
                     + (f"{fp:.1f} s" if fp >= 0 else "none in the window"),
                     f"idle UI {c['ui_fps_idle']:.1f} fps (same run)",
                     f"{c['fps_ratio_solving_vs_idle']:.2f}"))
    return rows


TABLES = {
    "smoke": (smoke_control_rows, "`build/bin/bench_smoke_control` (issue 3)"),
    "articulated": (articulated_rows, "`build/bin/bench_articulated` (issue 6; full tables in engine/articulated/README.md)"),
    "liquid": (liquid_rows, "`build/bin/bench_liquid` (issue 7; engine/liquid/README.md)"),
    "soft": (soft_rows, "`build/bin/bench_soft` (issue 5; engine/soft/README.md)"),
    "editor": (editor_rows, "`build/bin/bench_editor` (issue 4; editor/README.md)"),
}


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "bench/results")
    for path in sorted(root.glob("*.json")):
        d = json.loads(path.read_text())
        print("| case | Pliant | baseline | ratio |")
        print("|---|---|---|---|")
        if path.stem in TABLES:
            fn, how = TABLES[path.stem]
            for r in fn(d):
                print("| " + " | ".join(r) + " |")
            print(f"\n{path.stem}: {how}.\n")
        elif isinstance(d, dict) and d.get("bench") == "smoke_sim":
            for r in smoke_sim_rows(d):
                print("| " + " | ".join(r) + " |")
            m = d.get("machine", {})
            print(f"\nsmoke_sim: {d.get('mode')} mode, {m.get('nproc')} x {m.get('cpu')}, "
                  f"OMP_WAIT_POLICY={m.get('omp_wait_policy')}, load average at start "
                  f"{m.get('load_average_at_start')} (`build/bin/bench_smoke_sim`).\n")


if __name__ == "__main__":
    main()
