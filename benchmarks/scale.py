"""How the solver's cost grows with the number of positions and of groups (issue 5, item 4).

    python benchmarks/scale.py [--repeat 5] [--out /tmp/sheetkin-scale] [--max-positions 1e7]
                               [--chain-positions 1e5 1e6] [--quick]

(a) positions: the four-bar (workbooks/fourbar.toml) at 1e2 ... 1e7 crank positions, timed
    through `solve_table` (the solver into its preallocated table: contract columns and
    det_g*) and through the public `compute` (the same plus the DataFrame and the toggle
    flags); best and median of --repeat runs after a warm-up, wall clock.
(b) groups: a synthetic chain (chain_scene_text below) of 1, 2, 5, 10, 20, 50 groups at
    1e5 (and 1e6) positions, through solve_table; seconds, positions/s and
    group-positions/s (positions x groups / s), and the time per position per group, which
    is constant when the cost is linear in the groups.
(c) scale.png in --out: two log-log panels, time against positions (slope-1 reference)
    and time against groups (linear reference).
Peak memory at the largest size is the VmHWM of a fresh process that solves once.
Target (issue 5): linear in both, >= 5 million group-positions per second.

The synthetic chain is also what tests/kinematics/test_scale_chain.py checks; it assembles over the
whole crank revolution for any number of groups (checked up to 50 and more).
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

import importlib  # noqa: E402

import sheetkin  # noqa: E402

# the module (sheetkin.compute, the attribute, is the function; `import sheetkin` loads
# the module lazily, on first use, since issue 15)
C = importlib.import_module("sheetkin.kinematics.table")

# ---------------------------------------------------------------------------------------
# Synthetic chain
# ---------------------------------------------------------------------------------------
# Group 1 is a Grashof crank-rocker four-bar (crank 0.10, coupler 0.35, rocker 0.30,
# ground 0.38: s + l = 0.48 <= p + q = 0.65; transmission angle 50..95 deg). Every later
# group is driven by a [[point]] P<g> fixed on the current "driver", a link turning about a
# frame point (the last rocker or slotted lever):
#   RRR  P<g> - B<g> - F<g>, F<g> a new frame point: a rocker-rocker four-bar close to a
#        parallelogram (coupler ~ ground, output rocker ~ input radius), so the output
#        rocker repeats the input's swing instead of amplifying or damping it along the
#        chain; the ground direction is set 90 +- (up to 35) deg from the middle of the
#        input's swing, and the output rocker's length steers its half-swing back to ~25
#        deg. Its rocker becomes the next driver.
#   RPR  (mixed in every 6th group, g = 4, 10, 16, ...) a block on P<g> sliding in a
#        slotted lever that turns about F<g>, a frame point 0.15 r from the driver's pivot:
#        the lever nearly repeats the swing, |F P| >= 0.85 r never vanishes. The lever
#        becomes the next driver.
#   RRP  (every 6th group, g = 6, 12, ...) a side branch: coupler P<g> - B<g> and a slider
#        B<g> on a fixed guide laid along P<g>'s swing, offset so the coupler stays within
#        ~50 deg of the guide. The driver stays the same.
# Each candidate is checked over a 1440-position design grid (positions of the rounded,
# written values): the group assembles and its toggle measure stays above DESIGN_MIN;
# otherwise it is redrawn (seeded, so a (n, seed) pair always gives the same text).

DESIGN_MIN = 0.5             # min |det_g| of a group over the design grid (RRR: sin of the transmission angle)
_GRID = np.radians(np.arange(0.0, 360.0, 0.25))
_CRANK, _OMEGA, _EPSILON = 0.10, 10.0, 2.0


def _e(angle):
    return np.cos(angle), np.sin(angle)


def _circles(px, py, fx, fy, l2, l3, branch):
    """N with |P N| = l2, |F N| = l3, left (+1) or right (-1) of P -> F; None if it cannot assemble."""
    dx, dy = fx - px, fy - py
    d2 = dx * dx + dy * dy
    a = (d2 + l2 * l2 - l3 * l3) / (2.0 * d2)           # along P->F, in units of |PF|
    h2 = l2 * l2 / d2 - a * a                           # across, squared, same units
    if np.any(h2 <= 0):
        return None
    h = branch * np.sqrt(h2)
    return px + a * dx - h * dy, py + a * dy + h * dx


def _sin_between(ux, uy, vx, vy):
    return (ux * vy - uy * vx) / np.sqrt((ux * ux + uy * uy) * (vx * vx + vy * vy))


def _r6(x) -> float:
    return round(float(x), 6)


def _fmt(x) -> str:
    return repr(_r6(x) + 0.0)


def _group_kind(g: int, mix: bool) -> str:
    if mix and g >= 4 and g % 6 == 4:
        return "RPR"
    if mix and g >= 6 and g % 6 == 0:
        return "RRP"
    return "RRR"


def chain_scene_text(n_groups: int, seed: int = 0, *, mix: bool = True, tries: int = 2000) -> str:
    """A scene (TOML text) of a crank and `n_groups` Assur groups in a chain, assembling
    over the whole revolution with every group's |det| >= DESIGN_MIN (see above).

    mix=False gives RRR dyads only; mix=True puts an RPR (slotted lever) every 6th group
    from the 4th and an RRP (slider) every 6th from the 6th.
    """
    if n_groups < 1:
        raise ValueError("n_groups must be >= 1")
    rng = np.random.default_rng(seed)
    frame = {"O": (0.0, 0.0), "F1": (0.38, 0.0)}
    groups: list[str] = []
    points: list[str] = []

    # group 1: the four-bar, O - A - B1 - F1
    cx, cy = _CRANK * np.cos(_GRID), _CRANK * np.sin(_GRID)
    bx, by = _circles(cx, cy, *frame["F1"], 0.35, 0.30, 1)
    assert np.min(np.abs(_sin_between(bx - cx, by - cy, bx - 0.38, by))) > DESIGN_MIN
    groups.append(_rrr(1, "A", "B1", "F1", 0.35, 0.30, 1))
    # the driver: (link, pivot name, pivot xy, its angle over the grid, unwrapped)
    drv = (3, "F1", frame["F1"], np.unwrap(np.arctan2(by, bx - 0.38)))

    for g in range(2, n_groups + 1):
        kind = _group_kind(g, mix)
        link, pname, (ox, oy), theta = drv
        for _ in range(tries):
            r = _r6(rng.uniform(0.20, 0.35))
            alpha = rng.uniform(-0.7, 0.7)
            along, across = _r6(r * np.cos(alpha)), _r6(r * np.sin(alpha))
            c, s = _e(theta)
            px, py = ox + along * c - across * s, oy + along * s + across * c
            psi = theta + np.arctan2(across, along)         # direction pivot -> P
            mid, half = 0.5 * (psi.max() + psi.min()), 0.5 * (psi.max() - psi.min())
            if kind == "RRR":
                d = rng.uniform(0.25, 0.45)
                side = rng.choice((-1, 1))
                room = max(0.0, math.radians(60.0) - half - math.radians(5.0))
                beta = mid + side * math.pi / 2 + rng.uniform(-1, 1) * min(room, math.radians(35.0))
                fx, fy = _r6(ox + d * math.cos(beta)), _r6(oy + d * math.sin(beta))
                l2 = _r6(math.hypot(fx - ox, fy - oy) * rng.uniform(0.97, 1.03))
                gain = float(np.clip(half / math.radians(25.0), 0.8, 1.25))
                l3 = _r6(r * gain * rng.uniform(0.97, 1.03))
                branch = -int(side)
                n = _circles(px, py, fx, fy, l2, l3, branch)
                if n is None:
                    continue
                nx, ny = n
                if np.min(np.abs(_sin_between(nx - px, ny - py, nx - fx, ny - fy))) < DESIGN_MIN:
                    continue
                frame[f"F{g}"] = (fx, fy)
                groups.append(_rrr(g, f"P{g}", f"B{g}", f"F{g}", l2, l3, branch))
                new = (2 * g + 1, f"F{g}", (fx, fy), np.unwrap(np.arctan2(ny - fy, nx - fx)))
            elif kind == "RPR":
                gam = rng.uniform(0, 2 * math.pi)
                fx, fy = _r6(ox + 0.15 * r * math.cos(gam)), _r6(oy + 0.15 * r * math.sin(gam))
                dist = np.hypot(px - fx, py - fy)
                if np.min(dist) / _CRANK < DESIGN_MIN:      # the solver's RPR measure: s / crank length
                    continue
                frame[f"F{g}"] = (fx, fy)
                groups.append(f'[[group]]\ntype   = "RPR"\nlinks  = [{2 * g}, {2 * g + 1}]\n'
                              f'joints = ["P{g}", "F{g}"]\n')
                new = (2 * g + 1, f"F{g}", (fx, fy), np.unwrap(np.arctan2(py - fy, px - fx)))
            else:   # RRP side branch
                length = _r6(rng.uniform(0.25, 0.40))
                # guide along the chord of P's swing, through its middle, offset across
                i, j = int(np.argmin(psi)), int(np.argmax(psi))
                ang = math.atan2(py[j] - py[i], px[j] - px[i])
                ux, uy = math.cos(ang), math.sin(ang)
                off = rng.uniform(-0.5, 0.5) * length
                mx, my = 0.5 * (px[i] + px[j]), 0.5 * (py[i] + py[j])
                gx, gy = _r6(mx - off * uy), _r6(my + off * ux)
                ang_deg = _r6(math.degrees(ang))
                ux, uy = math.cos(math.radians(ang_deg)), math.sin(math.radians(ang_deg))
                h = -(px - gx) * uy + (py - gy) * ux
                if np.max(np.abs(h)) / length > math.sqrt(1 - DESIGN_MIN ** 2):
                    continue
                branch = int(rng.choice((-1, 1)))
                groups.append(f'[[group]]\ntype   = "RRP"\nlinks  = [{2 * g}, {2 * g + 1}]\n'
                              f'joints = ["P{g}", "B{g}"]\nlength = {_fmt(length)}\n'
                              f'guide  = {{ through = [{_fmt(gx)}, {_fmt(gy)}], angle_deg = {_fmt(ang_deg)} }}\n'
                              f'branch = {branch}\n')
                new = drv
            break
        else:
            raise RuntimeError(f"chain_scene_text: no {kind} group {g} found in {tries} tries")
        points.append(f'[[point]]\nname   = "P{g}"\nlink   = {link}\nfrom   = "{pname}"\n'
                      f'along  = {_fmt(along)}\nacross = {_fmt(across)}\n')
        drv = new

    kinds = [_group_kind(g, mix) for g in range(1, n_groups + 1)]
    head = (f'# Synthetic chain for benchmarks/scale.py: {n_groups} groups '
            f'({kinds.count("RRR")} RRR, {kinds.count("RPR")} RPR, {kinds.count("RRP")} RRP), seed {seed}\n'
            f'title = "Synthetic chain of {n_groups} groups (seed {seed})"\n\n[frame]\n')
    head += "".join(f"{k} = [{_fmt(x)}, {_fmt(y)}]\n" for k, (x, y) in frame.items())
    head += (f'\n[crank]\npivot     = "O"\njoint     = "A"\nlength    = {_CRANK}\nphi0_deg  = 0.0\n'
             f'step_deg  = 30.0\npositions = 13\nomega     = {_OMEGA}\nepsilon   = {_EPSILON}\n\n')
    return head + "\n".join(groups) + ("\n" if points else "") + "\n".join(points)


def _rrr(g, j1, n, j2, l2, l3, branch) -> str:
    return (f'[[group]]\ntype    = "RRR"\nlinks   = [{2 * g}, {2 * g + 1}]\n'
            f'joints  = ["{j1}", "{n}", "{j2}"]\nlengths = [{_fmt(l2)}, {_fmt(l3)}]\nbranch  = {branch}\n')


# ---------------------------------------------------------------------------------------
# Benchmark
# ---------------------------------------------------------------------------------------

def timings(fn, repeat: int, min_total: float = 0.3, max_runs: int = 300) -> tuple[float, float]:
    """(best, median) wall time after one warm-up run: at least `repeat` runs, more (up to
    max_runs) until they add up to min_total seconds, so that millisecond runs on a noisy
    VM are sampled enough for a stable best."""
    fn()
    times = []
    while len(times) < repeat or (sum(times) < min_total and len(times) < max_runs):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times), float(np.median(times))


def _status_mb(field: str) -> float:
    """VmRSS / VmHWM of this process in MB (not ru_maxrss: Linux keeps it across execve)."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith(field + ":"):
            return int(line.split()[1]) / 1024
    raise RuntimeError(f"no {field} in /proc/self/status")


def _scene(which: str):
    if which == "fourbar":
        return sheetkin.load_scene(ROOT / "workbooks" / "fourbar.toml")
    return sheetkin.parse_scene(chain_scene_text(int(which)))


def memory_child(which: str, n: int, how: str) -> None:
    """Run once in a fresh process: print resident sizes (MB) as JSON."""
    scene = _scene(which)
    phi = np.linspace(0.0, 360.0, n, endpoint=False)
    base = _status_mb("VmRSS")
    t = time.perf_counter()
    if how == "compute":
        out = sheetkin.compute(scene, phi)
        held = out.memory_usage(deep=True).sum() / 2**20
    else:
        _, table, _ = C.solve_table(scene, phi)
        held = table.nbytes / 2**20
    first = time.perf_counter() - t
    print(json.dumps({"base_mb": base, "peak_mb": _status_mb("VmHWM"), "first_run_s": first, "held_mb": held}))


def memory(which: str, n: int, how: str) -> dict:
    out = subprocess.run([sys.executable, __file__, "--memory-child", which, str(n), how],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def _n_label(n: int) -> str:
    e = round(math.log10(n))
    return f"1e{e}" if 10 ** e == n else f"{n:g}"


def bench_positions(sizes, repeat, compute_max):
    scene = _scene("fourbar")
    ncols = len(C.table_names(scene))
    rows = []
    for n in sizes:
        phi = np.linspace(0.0, 360.0, n, endpoint=False)
        rep = repeat if n < 10**7 else max(3, repeat // 2)
        s_best, s_med = timings(lambda phi=phi: C.solve_table(scene, phi), rep)
        if n <= compute_max:
            c_best, c_med = timings(lambda phi=phi: sheetkin.compute(scene, phi), rep)
        else:
            c_best = c_med = float("nan")
        rows.append(dict(n=n, table_mb=ncols * 8 * n / 2**20, s_best=s_best, s_med=s_med,
                         c_best=c_best, c_med=c_med))
        print(f"  {_n_label(n):>5}: solve_table {s_best:.4g} / {s_med:.4g} s, "
              f"compute {c_best:.4g} / {c_med:.4g} s", flush=True)
    return rows


def bench_groups(counts, n, repeat):
    phi = np.linspace(0.0, 360.0, n, endpoint=False)
    rows = []
    for k in counts:
        scene = _scene(str(k))
        ncols = len(C.table_names(scene))
        best, med = timings(lambda scene=scene: C.solve_table(scene, phi), repeat)
        rows.append(dict(groups=k, n=n, cols=ncols, best=best, med=med))
        print(f"  {k:>3} groups x {_n_label(n)}: {best:.4g} / {med:.4g} s", flush=True)
    return rows


def chart(pos_rows, group_rows_by_n, path: Path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.4))
    ns = np.array([r["n"] for r in pos_rows], dtype=float)
    s = np.array([r["s_best"] for r in pos_rows])
    c = np.array([r["c_best"] for r in pos_rows])
    a.loglog(ns, s, "o-", label="solve_table (best)")
    ok = np.isfinite(c)
    a.loglog(ns[ok], c[ok], "s-", label="compute (best)")
    ref = s[-1] * ns / ns[-1]                    # slope 1 through the largest point
    a.loglog(ns, ref, "k--", lw=0.8, label="slope 1")
    a.set_xlabel("crank positions")
    a.set_ylabel("seconds")
    a.set_title("four-bar: time vs positions")
    a.grid(True, which="both", alpha=0.3)
    a.legend()
    for n, rows in group_rows_by_n.items():
        k = np.array([r["groups"] for r in rows], dtype=float)
        t = np.array([r["best"] for r in rows])
        line, = b.loglog(k, t, "o-", label=f"solve_table, {_n_label(n)} positions")
        b.loglog(k, t[-1] * k / k[-1], "--", color=line.get_color(), lw=0.8,
                 label=f"linear ({t[-1] / k[-1] / n * 1e9:.0f} ns per group-position)")
    b.set_xlabel("groups in the chain")
    b.set_ylabel("seconds")
    b.set_title("synthetic chain: time vs groups")
    b.grid(True, which="both", alpha=0.3)
    b.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--out", default="/tmp/sheetkin-scale")
    ap.add_argument("--max-positions", type=float, default=1e7)
    ap.add_argument("--compute-max", type=float, default=1e7,
                    help="largest size also timed through compute (the DataFrame path)")
    ap.add_argument("--chain-positions", type=float, nargs="+", default=[1e5, 1e6])
    ap.add_argument("--groups", type=int, nargs="+", default=[1, 2, 5, 10, 20, 50])
    ap.add_argument("--quick", action="store_true", help="1e2..1e5 positions, chains at 1e4 (a smoke run)")
    ap.add_argument("--tiny", action="store_true",
                    help="a smoke run for CI: 1e2..1e3 positions, 1 and 2 groups, once")
    ap.add_argument("--memory-child", nargs=3, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.memory_child:
        which, n, how = args.memory_child
        memory_child(which, int(n), how)
        return 0
    if args.quick:
        args.max_positions, args.chain_positions, args.repeat = 1e5, [1e4], 2
    if args.tiny:
        args.max_positions, args.compute_max, args.chain_positions = 1e3, 1e3, [1e2]
        args.groups, args.repeat = [1, 2], 1
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    print(f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, python "
          f"{platform.python_version()}, numpy {np.__version__}; solve_table chunk {C.CHUNK}, "
          f"best / median of {args.repeat} after a warm-up", flush=True)

    sizes = [10**e for e in range(2, 8) if 10**e <= args.max_positions]
    print("(a) four-bar, time vs positions", flush=True)
    pos_rows = bench_positions(sizes, args.repeat, args.compute_max)
    print("(b) synthetic chain, time vs groups", flush=True)
    group_rows = {int(n): bench_groups(args.groups, int(n), args.repeat) for n in args.chain_positions}
    png = out / "scale.png"
    chart(pos_rows, group_rows, png)

    big = sizes[-1]
    mem = {how: memory("fourbar", big, how) for how in ("solve_table", "compute") if big <= args.compute_max
           or how == "solve_table"}
    kbig, nbig = max(args.groups), int(max(args.chain_positions))
    mem_chain = memory(str(kbig), nbig, "solve_table")

    print(f"\n### Time vs positions (four-bar: 1 RRR group, {len(C.table_names(_scene('fourbar')))} "
          "table columns)\n")
    print("| positions | solve_table s (best / median) | positions/s (best) | compute s (best / median) "
          "| positions/s (best) | ns per position (solve_table) |")
    print("|---:|---:|---:|---:|---:|---:|")
    for r in pos_rows:
        n = r["n"]
        cs = "n/a" if not math.isfinite(r["c_best"]) else f"{r['c_best']:.3g} / {r['c_med']:.3g}"
        cr = "n/a" if not math.isfinite(r["c_best"]) else f"{n / r['c_best']:.3g}"
        print(f"| {_n_label(n)} | {r['s_best']:.3g} / {r['s_med']:.3g} | {n / r['s_best']:.3g} | {cs} | {cr} "
              f"| {r['s_best'] / n * 1e9:.0f} |")
    ns = np.array([r["n"] for r in pos_rows], dtype=float)
    ts = np.array([r["s_best"] for r in pos_rows])
    sel = ns >= 1e5
    if sel.sum() >= 2:
        print(f"\nlinearity: solve_table time ~ positions^{np.polyfit(np.log(ns[sel]), np.log(ts[sel]), 1)[0]:.2f} "
              f"over {_n_label(int(ns[sel].min()))}..{_n_label(int(ns[sel].max()))} positions")
    for n, rows in group_rows.items():
        print(f"\n### Time vs groups (synthetic chain, {_n_label(n)} positions, solve_table)\n")
        print("| groups | columns | s (best / median) | positions/s | group-positions/s | ns per group-position |")
        print("|---:|---:|---:|---:|---:|---:|")
        for r in rows:
            k = r["groups"]
            print(f"| {k} | {r['cols']} | {r['best']:.3g} / {r['med']:.3g} | {n / r['best']:.3g} "
                  f"| {n * k / r['best']:.3g} | {r['best'] / (n * k) * 1e9:.0f} |")
        # linearity: log-log slope of time over groups (1 = linear) beyond the fixed overhead
        k = np.array([r["groups"] for r in rows], dtype=float)
        t = np.array([r["best"] for r in rows])
        per = t / (k * n) * 1e9
        sel = k >= 5
        if sel.sum() < 2:                   # a smoke run (--tiny): too few chains for a slope
            continue
        expo = np.polyfit(np.log(k[sel]), np.log(t[sel]), 1)[0]
        steps = ", ".join(f"{int(k[i])}->{int(k[i + 1])}: {math.log(t[i + 1] / t[i]) / math.log(k[i + 1] / k[i]):.2f}"
                          for i in range(len(k) - 1))
        print(f"\nlinearity: time ~ groups^{expo:.2f} over {int(k[sel].min())}..{int(k[sel].max())} groups "
              f"(log-log slopes {steps}); ns per group-position from {per[sel].min():.0f} to "
              f"{per[sel].max():.0f} (ratio {per[sel].max() / per[sel].min():.2f})")
    print()
    for how, m in mem.items():
        print(f"memory, four-bar x {_n_label(big)} via {how} (fresh process): peak RSS (VmHWM) "
              f"{m['peak_mb']:.0f} MB, {m['peak_mb'] - m['base_mb']:.0f} MB above the imported baseline; "
              f"result holds {m['held_mb']:.0f} MB; first (cold) run {m['first_run_s']:.2f} s")
    print(f"memory, {kbig}-group chain x {_n_label(nbig)} via solve_table (fresh process): peak RSS "
          f"{mem_chain['peak_mb']:.0f} MB, {mem_chain['peak_mb'] - mem_chain['base_mb']:.0f} MB above baseline; "
          f"table {mem_chain['held_mb']:.0f} MB; first run {mem_chain['first_run_s']:.2f} s")
    print(f"chart: {png}")
    (out / "scale.json").write_text(json.dumps({"positions": pos_rows, "groups": group_rows,
                                                "memory": mem, "memory_chain": mem_chain}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
