#!/usr/bin/python3
"""Byte-identity check for refactors: the same plans, estimates and missions
from two builds of `gather`.

  tools/identity_check.py --before OLD_GATHER --after NEW_GATHER
  make identity-check REF=<commit>   (builds REF's gather in a worktree first)

On maps/office and ../shared/maps/ipa/office_a: `gather plan` (the whole
sweep) must give the same plan.yaml and the same report.csv apart from its
timing columns (*_ms) and the same labels.png pixels (the PNG encoder may
differ), and `gather sim` of that plan (3 seeds x 10 cycles)
and `gather run` (in one process, 1 seed x 3 cycles) the same goals.csv.
Both sweeps' best plans use no collector, so two plans with collectors are
compared too: office_a pap:4 (the end-to-end tests' plan: two workers of
collectors) and office pap:4 with the association off (every segment off
the coverage served by a collector).
Prints one line per file and exits 1 on any difference.
"""
import argparse
import csv
import io
import os
import subprocess
import sys
import tempfile

from PIL import Image

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
OFFICE = os.path.join(REPO, "maps", "office.scenario.yaml")
OFFICE_A = os.path.join(REPO, "..", "shared", "maps", "ipa", "office_a.scenario.yaml")
# (name, scenario, extra `gather plan` arguments)
CASES = [("office", OFFICE, []),
         ("office_a", OFFICE_A, []),
         ("office_a_pap4", OFFICE_A, ["--config", "pap:4"]),
         ("office_pap4_grown", OFFICE, ["--config", "pap:4", "--association", "off"])]


def run(argv):
    p = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.exit("identity_check: %s failed (%d): %s" % (" ".join(argv), p.returncode, p.stderr[-800:]))


def report_without_times(path):
    rows = list(csv.reader(open(path)))
    keep = [i for i, name in enumerate(rows[0]) if not name.endswith("_ms")]
    out = io.StringIO()
    csv.writer(out).writerows([[r[i] for i in keep] for r in rows])
    return out.getvalue()


def label_pixels(path):
    img = Image.open(path)
    return "%s %s %s" % (img.mode, img.size, bytes(img.tobytes()).hex())


def outputs(gather, scenario, plan_args, d):
    plan = os.path.join(d, "plan")
    run([gather, "plan", scenario, "--out", plan] + plan_args)
    run([gather, "sim", plan, "--cycles", "10", "--seeds", "3", "--out", os.path.join(d, "sim")])
    run([gather, "run", plan, "--cycles", "3", "--out", os.path.join(d, "run")])
    return {"plan.yaml": open(os.path.join(plan, "plan.yaml")).read(),
            "labels.png (pixels)": label_pixels(os.path.join(plan, "labels.png")),
            "report.csv (without *_ms)": report_without_times(os.path.join(plan, "report.csv")),
            "sim goals.csv": open(os.path.join(d, "sim", "goals.csv")).read(),
            "run goals.csv": open(os.path.join(d, "run", "goals.csv")).read()}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--before", required=True)
    ap.add_argument("--after", required=True)
    a = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="gather_identity_")
    differ = 0
    for name, scenario, plan_args in CASES:
        before = outputs(a.before, scenario, plan_args, os.path.join(tmp, name, "before"))
        after = outputs(a.after, scenario, plan_args, os.path.join(tmp, name, "after"))
        for f in before:
            same = before[f] == after[f]
            differ += not same
            print("%s %s: %s" % ("same" if same else "DIFF", name, f))
    print("identity check: %s (files in %s)" % ("all identical" if not differ else "%d differ" % differ, tmp))
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
