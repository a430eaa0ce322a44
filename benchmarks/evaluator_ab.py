"""Before and after, same run: `sheetkin evaluate` of the 360-column shaper as a process
(CPU and wall time) and `evaluate()` in-process (CPU), for two source trees interleaved
round by round, and LibreOffice's `soffice --convert-to` of the same book (CPU of its
process tree, and wall time). CPU time is what a loaded machine distorts least.

    python -m sheetkin workbook workbooks/shaper.toml --positions 360 --step-deg -1 -o /tmp/xlb/shaper360.xlsx
    python benchmarks/evaluator_ab.py ROUNDS [BEFORE_TREE AFTER_TREE]
"""
import os
import resource
import shutil
import statistics
import subprocess
import sys
import time

book = "/tmp/xlb/shaper360.xlsx"
trees = ({"before": sys.argv[2], "after": sys.argv[3]} if len(sys.argv) > 3
         else {"before (main)": "/work/main", "after (xlsx)": "/work/wt/xlsx"})
code_eval = ("import time,sys; from sheetkin.xlsx.evaluator import evaluate; t=time.process_time(); "
             "b=evaluate(sys.argv[1]); print(time.process_time()-t)")
def cpu_of(cmd, env):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    out = subprocess.run(cmd, check=True, env=env, capture_output=True, text=True, cwd="/tmp/xlb")
    wall = time.perf_counter() - t
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime), wall, out.stdout
res = {k: {"process cpu": [], "process wall": [], "evaluate cpu": []} for k in trees}
lo_cpu = []
for _rnd in range(int(sys.argv[1])):
    for name, root in trees.items():
        env = {**os.environ, "PYTHONPATH": root}
        cpu, wall, _ = cpu_of([sys.executable, "-m", "sheetkin", "evaluate", book, "--format", "csv",
                               "-o", "/dev/null"], env)
        res[name]["process cpu"].append(cpu)
        res[name]["process wall"].append(wall)
        _, _, out = cpu_of([sys.executable, "-c", code_eval, book], env)
        res[name]["evaluate cpu"].append(float(out))
for name, r in res.items():
    print(name, "; ".join(f"{k}: best {min(v):.3f} s, median {statistics.median(v):.3f} s" for k, v in r.items()))
# LibreOffice: CPU of the soffice process tree (children) for one file, same run

for i in range(2):
    out = f"/tmp/xlb/lo_cpu{i}"
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    cpu, wall, _ = cpu_of(["soffice", "-env:UserInstallation=file:///tmp/xlb/lo-profile", "--headless", "--norestore",
                           "--convert-to", "xlsx:Calc MS Excel 2007 XML", "--outdir", out, book], os.environ)
    lo_cpu.append((cpu, wall))
    print("LibreOffice soffice --convert-to (1 file):", f"cpu {cpu:.2f} s, wall {wall:.2f} s")
