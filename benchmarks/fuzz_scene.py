"""Count the scene fuzzer's outcomes on many cases (README, "Reliability").

    python benchmarks/fuzz_scene.py [--examples N]

Runs tests/kinematics/test_fuzz_scene.py's two generators (random documents from the scene's keys,
random snippets in the bundled scenes) through its check, N cases each (hypothesis,
derandomized), and prints: cases tried, refused cleanly (one-line SceneError), computed,
refused by compute in one line, and crashes (anything else: must be 0).
"""
from __future__ import annotations

import argparse
import collections
import sys
import time
import traceback
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests"), str(ROOT / "tests" / "kinematics")]

import test_fuzz_scene as fz  # noqa: E402
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--examples", type=int, default=5000, help="cases per generator (default 5000)")
    ap.add_argument("--tiny", action="store_true", help="a smoke run for CI: 20 cases per generator")
    args = ap.parse_args()
    if args.tiny:
        args.examples = 20
    counts: dict[str, collections.Counter] = {}
    crashes = []

    def record(kind, text):
        try:
            outcome = fz.check_document(text)
        except Exception as e:          # an assertion of the check, or anything else: a crash
            outcome = "crash"
            crashes.append((kind, type(e).__name__, str(e)[:200], text[:300]))
            traceback.print_exc(limit=3)
        counts.setdefault(kind, collections.Counter())[outcome] += 1

    @settings(max_examples=args.examples, **fz.SETTINGS)
    @given(fz.documents())
    def documents(text):
        record("documents", text)

    @settings(max_examples=args.examples, **fz.SETTINGS)
    @given(st.sampled_from(fz.TEXTS), st.integers(0, 10 ** 6),
           st.one_of(st.sampled_from(fz.SNIPPETS), st.text(max_size=30)), st.booleans())
    def snippets(text, where, snippet, replace):
        lines = text.splitlines()
        k = where % (len(lines) + 1)
        if replace and k < len(lines):
            lines[k] = snippet
        else:
            lines.insert(k, snippet)
        record("snippets", "\n".join(lines) + "\n")

    t0 = time.perf_counter()
    documents()
    snippets()
    total = collections.Counter()
    print(f"{'generator':<12}{'tried':>8}{'refused':>9}{'computed':>10}{'compute refused':>17}{'crashes':>9}")
    for kind, c in list(counts.items()) + [("total", None)]:
        c = c if c is not None else total
        if kind != "total":
            total.update(c)
        print(f"{kind:<12}{sum(c.values()):>8}{c['refused']:>9}{c['computed']:>10}"
              f"{c['compute refused']:>17}{c['crash']:>9}")
    print(f"({time.perf_counter() - t0:.0f} s)")
    for c in crashes[:10]:
        print("CRASH", c)
    return 1 if crashes else 0


if __name__ == "__main__":
    sys.exit(main())
