#!/usr/bin/env python3
"""Every engine on every backend, side by side in one run (issue 42's table).

    bench/engines.py RELIEF IMAGE_TOOL DATA OUT [--backends scalar,host,opencl]
                     [--reps N] [--cases NAME,...] [--bench-complete PATH]
                     [--points-tool PATH] [--profile]

RELIEF is the relief program, IMAGE_TOOL tests/image_tool (it makes the
tiled and masked inputs), --points-tool bench/points_bench_tool (it makes
the 226 405-point bunny; default beside RELIEF in bench/), DATA ../shared/data, OUT a folder for the inputs
made, the outputs and engines.csv / engines.md. Each case runs the command
line `relief ... -o OUT --backend B --quiet` for each backend in turn within
a repetition (a noisy machine slows every backend alike), N repetitions
(the scalar reference once more than ten seconds), and the wall time of the
whole process is kept: its median per backend, and the ratio of medians
against scalar. Every backend's output is compared byte for byte with the
first backend's: a row that differs says so and the script exits 1.

With --bench-complete, paper 000's bark, exhaustive, growth only (bench/
bench_complete, the bark of bench/run.sh's papers case) is a row too: its
growth's median as bench_complete prints it; the scalar reference, 6.6
minutes on one core, runs only when asked for with --bark-scalar.

With --profile (and opencl among the backends), each case's OpenCL command
runs once more, untimed, with RELIEF_OPENCL_PROFILE=1: where its engine's
time went on the device (each kernel's, the writes' and the reads' count,
bytes and device seconds, against the engine's lifetime), appended to
OUT/profile.txt and printed (docs/devices.md, "Where the time goes").
"""
import argparse
import csv
import filecmp
import os
import re
import statistics
import subprocess
import sys
import time

BARK = ["--kind", "cylinder-bark", "--colour", "--vertices", "7150", "--spacing", "0.0333",
        "--window", "3", "--rotations", "4"]
FRAG_DISC = "1.65835,1.88511,1.06949,0.12"  # a 0.12 m ball on the floor of frag_115
BUNNY_BALL = "-0.0336,0.0816,0.0446,0.02"  # bench/points.py's 2 cm ball on the bunny's flank


def run(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit("engines: %s: exit %d\n%s" % (" ".join(cmd), r.returncode, r.stderr[-2000:]))
    return r


def prepare_bunny(points_tool, data, inp):
    """Paper 002's size: the bunny scan sampled evenly to 240 000 points
    (226 405 after the cut) and a 2 cm ball cut from its flank, as
    bench/points.py makes it."""
    cap = os.path.join(inp, "bunny226k.ply")
    if os.path.exists(cap) or not points_tool:
        return
    smp, truth = os.path.join(inp, "bunny240k.ply"), os.path.join(inp, "bunny226k_truth.ply")
    run([points_tool, "sample", data + "/real/stanford_bunny/stanford-bunny.obj", "240000", "1",
         smp])
    run([points_tool, "cut-points", smp, cap, truth, BUNNY_BALL])
    os.remove(smp)
    os.remove(truth)


def prepare(relief, tool, data, inp):
    """The inputs: made here from DATA, or reused when already there."""
    os.makedirs(inp, exist_ok=True)
    made = {
        "demo.ply": [relief, "synth", "cylinder-bark", "--colour", "--seed", "1", "-o"],
        "astronaut_mask.png": [tool, "mask", None, "512", "512", "141", "141", "230", "230"],
        "grass2048.png": [tool, "tile", data + "/images/grass.png", None, "2048", "2048"],
        "grass2048_mask.png": [tool, "mask", None, "2048", "2048", "924", "924", "200", "200"],
        "atlas.png": [tool, "tile", data + "/images/coffee.png", None, "8192", "1024"],
        "atlas_mask.png": [tool, "mask", None, "8192", "1024"] + sum(
            ([str(500 + 1000 * i), "300", str(61 + 20 * i), "121"] for i in range(8)), []),
        "frag_cut.ply": [relief, "cut", data + "/real/open3d_frag115/frag_115.ply", "--ball",
                         FRAG_DISC, "-o"],
    }
    for name, cmd in made.items():
        path = os.path.join(inp, name)
        if os.path.exists(path):
            continue
        cmd = [path if c is None else c for c in cmd]
        if cmd[-1] == "-o":
            cmd.append(path)
        run(cmd)


def cases(data, inp):
    i = lambda n: os.path.join(inp, n)
    office = data + "/depth/office1.pcd"
    return [
        ("complete", "demo (bark, 1326 targets, defaults)", "ply", ["complete", i("demo.ply")]),
        ("image-fill", "astronaut 512 x 512, 230 x 230 hole", "png",
         ["image-fill", data + "/images/astronaut.png", "--mask", i("astronaut_mask.png")]),
        ("image-fill", "grass tiled to 2048 x 2048, 200 x 200 hole", "png",
         ["image-fill", i("grass2048.png"), "--mask", i("grass2048_mask.png")]),
        ("image-fill", "astronaut 512 x 512, 230 x 230 hole, --method jain", "png",
         ["image-fill", data + "/images/astronaut.png", "--mask", i("astronaut_mask.png"),
          "--method", "jain"]),
        ("image-fill", "coffee atlas 8192 x 1024, 8 holes, --atlas --method jain", "png",
         ["image-fill", i("atlas.png"), "--mask", i("atlas_mask.png"), "--atlas",
          "--method", "jain"]),
        ("depth-fill", "office1.pcd, --variant plain", "pcd",
         ["depth-fill", office, "--variant", "plain"]),
        ("depth-fill", "office1.pcd, --variant decompose (default)", "pcd",
         ["depth-fill", office]),
        ("depth-fill", "office1.pcd, decompose, waves of 64 (--batch 64)", "pcd",
         ["depth-fill", office, "--batch", "64"]),
        ("complete-points", "frag_115, 0.12 m ball cut, --grid-search brute", "ply",
         ["complete-points", i("frag_cut.ply"), "--grid-search", "brute"]),
        ("complete-points", "bunny, 226 405 points, 2 cm ball cut, --grid-search brute", "ply",
         ["complete-points", i("bunny226k.ply"), "--grid-search", "brute"]),
    ]


def time_case(relief, out, key, ext, args, backends, reps):
    times = {b: [] for b in backends}
    for rep in range(reps):
        for b in backends:
            if rep > 0 and b == "scalar" and times[b] and times[b][0] > 10.0:
                continue  # a slow reference once
            path = os.path.join(out, "%s_%s.%s" % (key, b, ext))
            t0 = time.perf_counter()
            run([relief] + args + ["-o", path, "--backend", b, "--quiet"])
            times[b].append(time.perf_counter() - t0)
    first = os.path.join(out, "%s_%s.%s" % (key, backends[0], ext))
    same = all(filecmp.cmp(first, os.path.join(out, "%s_%s.%s" % (key, b, ext)), shallow=False)
               for b in backends[1:])
    return {b: statistics.median(t) for b, t in times.items()}, same


def profile_case(relief, out, title, ext, args, bench_complete=None):
    """One more OpenCL run with RELIEF_OPENCL_PROFILE=1: its profile lines,
    appended to OUT/profile.txt."""
    env = dict(os.environ, RELIEF_OPENCL_PROFILE="1")
    if bench_complete:
        cmd = [bench_complete, "--case", "paper000-bark"] + BARK + [
            "--backends", "opencl", "--reps", "1"]
    else:
        cmd = [relief] + args + ["-o", os.path.join(out, "profile." + ext), "--backend",
                                 "opencl", "--quiet"]
    t0 = time.perf_counter()
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    wall = time.perf_counter() - t0
    lines = [l for l in r.stderr.splitlines() if l.startswith("relief: OpenCL profile")
             or l.startswith("relief:   ")]
    text = "## %s (whole run %.2f s, exit %d)\n%s\n\n" % (title, wall, r.returncode,
                                                          "\n".join(lines) or "(no profile)")
    with open(os.path.join(out, "profile.txt"), "a") as f:
        f.write(text)
    print(text, end="", flush=True)


def bark_row(bench_complete, out, backends, scalar):
    use = [b for b in backends if b != "scalar" or scalar]
    path = os.path.join(out, "bark.csv")
    if os.path.exists(path):
        os.remove(path)
    r = run([bench_complete, "--case", "paper000-bark"] + BARK +
            ["--backends", ",".join(use), "--reps", "2", "--scalar-reps", "1", "--csv", path])
    with open(path) as f:
        rows = [row for row in csv.DictReader(f) if row["stage"] == "grow"]
    med = {row["backend"]: float(row["median"]) for row in rows}
    same = all(row["identical"] in ("yes", "n/a") for row in rows)
    return med, same


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("relief")
    ap.add_argument("image_tool")
    ap.add_argument("data")
    ap.add_argument("out")
    ap.add_argument("--backends", default="scalar,host")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--cases", default="")
    ap.add_argument("--bench-complete", default="")
    ap.add_argument("--bark-scalar", action="store_true")
    ap.add_argument("--points-tool", default="")
    ap.add_argument("--profile", action="store_true")
    a = ap.parse_args()
    profile = a.profile and "opencl" in a.backends.split(",")
    if profile and os.path.exists(os.path.join(a.out, "profile.txt")):
        os.remove(os.path.join(a.out, "profile.txt"))
    backends = a.backends.split(",")
    inp = os.path.join(a.out, "in")
    prepare(a.relief, a.image_tool, a.data, inp)
    prepare_bunny(a.points_tool or os.path.join(os.path.dirname(a.relief), "bench",
                                                 "points_bench_tool"), a.data, inp)
    rows, ok = [], True
    for n, (engine, case, ext, args) in enumerate(cases(a.data, inp)):
        if a.cases and str(n + 1) not in a.cases.split(",") and engine not in a.cases.split(","):
            continue
        if not all(os.path.exists(x) for x in args if x.startswith(inp)):
            print("engines: %s, %s: its input was not made (no points tool)" % (engine, case))
            continue
        med, same = time_case(a.relief, a.out, "case%d" % (n + 1), ext, args, backends, a.reps)
        rows.append((engine, case, med, same))
        ok &= same
        print("engines: %s, %s: %s; %s" % (engine, case, ", ".join(
            "%s %.2f s" % (b, med[b]) for b in backends), "same bytes" if same else "DIFFERENT"),
            flush=True)
        if profile:
            profile_case(a.relief, a.out, "%s, %s" % (engine, case), ext, args)
    if a.bench_complete:
        med, same = bark_row(a.bench_complete, a.out, backends, a.bark_scalar)
        rows.append(("complete", "paper 000's bark, exhaustive, growth only", med, same))
        ok &= same
        print("engines: bark growth: %s" % med, flush=True)
        if profile:
            profile_case(a.relief, a.out, "complete, paper 000's bark, growth only", "", [],
                         a.bench_complete)
    with open(os.path.join(a.out, "engines.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["engine", "case"] + ["%s_s" % b for b in backends] + ["same_bytes"])
        for engine, case, med, same in rows:
            w.writerow([engine, case] + ["%.4f" % med[b] if b in med else "" for b in backends]
                       + [int(same)])
    others = [b for b in backends if b != "scalar"]
    head = "| engine | case | " + " | ".join(backends) + " | " + " | ".join(
        "%s / scalar" % b for b in others) + " | bytes |"
    lines = [head, "|" + " --- |" * (head.count("|") - 1)]
    for engine, case, med, same in rows:
        cells = ["%.2f s" % med[b] if b in med else "not run" for b in backends]
        ratios = ["%.2f" % (med["scalar"] / med[b]) if "scalar" in med and b in med else ""
                  for b in others]
        lines.append("| %s | %s | %s | %s | %s |" % (engine, case, " | ".join(cells),
                                                     " | ".join(ratios),
                                                     "same" if same else "DIFFERENT"))
    table = "\n".join(lines)
    with open(os.path.join(a.out, "engines.md"), "w") as f:
        f.write(table + "\n")
    print(table)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
