#!/usr/bin/env python3
"""docs/results.md from the work folder of bench/results.sh.

    bench/results_tables.py OUT COMMAND MACHINE COMMIT

OUT holds run/ (bench/same_output.sh run: knit/NAME, plan/NAME, demo,
record.sha256, times.txt) and seed/NAME (the paper's covers scheduled again
with --pattern seed). Prints Markdown: one table per subject.
"""
import collections
import json
import os
import re
import subprocess
import sys

sys.dont_write_bytecode = True  # no __pycache__ in bench/
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import stitch_mesh_table  # noqa: E402

PAPER_COVERS = ["bunny-qd", "fertility-qd", "rockerarm-qd", "torus-qd"]


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def table(header, align, rows):
    out = ["| " + " | ".join(header) + " |", "| " + " | ".join(align) + " |"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def seconds(value):
    if value is None:
        return "–"
    if value < 1:
        return "%.3f" % value
    return "%.2f" % value if value < 10 else "%.1f" % value


def plural(n, word):
    return f"{n} {word}" if n == 1 else f"{n} {word}s"


def minutes(value_s):
    return "%.0f min" % (value_s / 60)


def thousands(n):
    return f"{n:,}"


def obj_faces(path):
    faces = []
    with open(path) as f:
        for line in f:
            if line.startswith("f "):
                faces.append([int(t.split("/")[0]) - 1 for t in line.split()[1:]])
    return faces


def vertex_counts(folder):
    """(irregular, singular) interior vertices of proxy.obj with the corner
    counts of §4.1 (vanishing corners not counted), from labels.json."""
    labels = load(os.path.join(folder, "labels.json"))
    faces = obj_faces(os.path.join(folder, "proxy.obj"))
    corners = collections.Counter()
    edge_uses = collections.Counter()
    for f, face in enumerate(faces):
        vanishing = labels["vanishing_corner"][f]
        for i, v in enumerate(face):
            if i != vanishing:
                corners[v] += 1
            w = face[(i + 1) % len(face)]
            edge_uses[(min(v, w), max(v, w))] += 1
    boundary = {v for edge, n in edge_uses.items() if n == 1 for v in edge}
    interior = {v for face in faces for v in face} - boundary
    irregular = sum(1 for v in interior if corners[v] != 4)
    singular = sum(1 for v in interior if corners[v] % 4 != 0)
    return irregular, singular


def read_record(run):
    """Failed stages {label: exit code} and wall seconds {label: s}."""
    failed, wall = {}, {}
    with open(os.path.join(run, "record.sha256")) as f:
        for line in f:
            m = re.match(r"exit (\d+)  (\S+)", line)
            if m:
                failed[m.group(2)] = int(m.group(1))
    with open(os.path.join(run, "times.txt")) as f:
        for line in f:
            label, value, _ = line.split()
            wall[label] = float(value)
    return failed, wall


def first_error(log):
    try:
        with open(log) as f:
            for line in f:
                if "error" in line:
                    return line.strip()
    except OSError:
        pass
    return "(no message)"


def cut_rows(knit, names):
    rows = []
    for name in names:
        cut = load(os.path.join(knit, name, "cut.json"))
        if cut is None:
            continue
        r = cut["report"]
        irregular, singular = vertex_counts(os.path.join(knit, name))
        rows.append([name, r["input"]["faces"], r["proxy"]["method"], r["proxy"]["faces"],
                     irregular, singular, r["cut_edges"], r["arcs"], r["overlapping_faces"],
                     seconds(r["time_s"]["proxy"] + r["time_s"]["cut"])])
    return rows


def stitch_rows(knit, names):
    """The rows, how many meet every target, and the meshes whose stitch
    vertices lie more than half a wale from the garment."""
    rows, met, far = [], 0, []
    for name in names:
        folder = os.path.join(knit, name)
        report = load(os.path.join(folder, "stitch-mesh.json"))
        if report is None:
            continue
        cells = stitch_mesh_table.cells(folder)
        met += cells[-1] == "all met"
        off = report["report"]["off_surface"]["faces"]
        distance = report["report"]["surface_distance"]
        if distance["max_mm"] > 0.5 * report["report"]["gauge"]["wale_mm"]:
            far.append(name)
        rows.append([name] + cells + [off, "%.2f / %.4f" % (distance["max_mm"],
                                                            distance["mean_mm"]),
                                      seconds(report["report"]["seconds"])])
    return rows, met, far


def schedule_figures(folder):
    schedule = load(os.path.join(folder, "schedule.json"))
    if schedule is None:
        return None
    r = schedule["report"]
    pieces = r["pieces"]
    return {
        "pieces": len(pieces),
        "cuts": r["cuts"],
        "wale_seams": r["wale_seams"],
        "patches_moved": r["patches_moved"],
        "loops_set_aside": r["loops_set_aside"],
        "passes": sum(p["passes"] for p in pieces),
        "transfers": sum(p["transfers"] for p in pieces),
        "vm_warnings": sum(p["vm_warnings"] for p in pieces),
        "knit_time_s": sum(p["estimated_knit_time_s"] for p in pieces),
        "widest": max((p["width_needles"] for p in pieces), default=0),
        "seconds": r["time_s"],
    }


def schedule_rows(knit, names, wall):
    rows = []
    for name in names:
        s = schedule_figures(os.path.join(knit, name))
        if s is None:
            continue
        rows.append([name, s["pieces"], s["cuts"], s["wale_seams"], s["patches_moved"],
                     s["loops_set_aside"], s["widest"], thousands(s["passes"]),
                     thousands(s["transfers"]), s["vm_warnings"], minutes(s["knit_time_s"]),
                     seconds(s["seconds"]), seconds(wall.get("knit/" + name))])
    return rows


def plan_table(rows):
    """bench/plan_table.py's table for NAME=DIR:EXIT:WALL arguments."""
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "plan_table.py")
    return subprocess.run([sys.executable, script] + rows, check=True, capture_output=True,
                          text=True).stdout.rstrip("\n")


def wearability_rows(folders):
    rows = []
    for name, folder in folders:
        wear = load(os.path.join(folder, "wearability.json"))
        cut = load(os.path.join(folder, "cut.json"))
        if wear is None or cut is None:
            continue
        s = wear["summary"]
        steps = sum(t["steps"] for a in wear["arcs"]
                    for t in a.get("wearability", {}).get("trials", []))
        rows.append([name, len(cut["arcs"]), s.get("sewn", "–"), s.get("laced", "–"),
                     s.get("tests", "–"), thousands(steps), "yes" if s["recut"] else "no",
                     seconds(s["seconds"])])
    return rows


def main(out, command, machine, commit):
    run = os.path.join(out, "run")
    knit = os.path.join(run, "knit")
    failed, wall = read_record(run)
    names = sorted(d for d in os.listdir(knit) if os.path.isdir(os.path.join(knit, d)))
    p = []
    p.append("# Results\n")
    p.append("The planner's current figures, all from one run of one binary over the shared test "
             "meshes (`../shared/meshes`). The page is written by the command below; to bring it "
             "up to date, run the command again rather than edit the tables.\n")
    p.append("```sh\n%s\n```\n" % command)
    p.append(f"Built from commit {commit}; the machine had {machine}. Times are wall seconds "
             "of that run and grow with the machine's load; the counts do not depend on it. "
             "`est. knit time` is the needle-bed VM's estimate of the machine's time "
             "(docs/vm.md), summed over a mesh's pieces.\n")

    # The knit branch.
    p.append("## The knit branch on every shared mesh\n")
    p.append("Each mesh scaled to 100 mm along its longest side, then `wearknit cut`, "
             "`wearknit stitch-mesh` and `wearknit schedule` with every option at its default "
             "(plain pattern); the garment alone, no wearer (`bench/same_output.sh run`).\n")
    knit_failures = {k: v for k, v in failed.items() if k.startswith("knit/")}
    if knit_failures:
        p.append("Stages that failed:\n")
        for label, code in sorted(knit_failures.items()):
            _, name, stage = label.split("/")
            log = os.path.join(knit, f"{name}.{stage}.log")
            p.append(f"- `{name}` {stage}, exit {code}: `{first_error(log)}`")
        p.append("")
    else:
        p.append(f"Every stage of all {len(names)} meshes ended with exit code 0.\n")

    p.append("### Cut (§4)\n")
    p.append("The garment's quad-dominant proxy (`input` when the mesh is used as it is, "
             "`instant-meshes` when triangle input is remeshed, docs/cutting.md) and its cut "
             "into one disc. Irregular vertices have other than four non-vanishing corners, "
             "singular ones a number not divisible by four (docs/cutting.md, §3); `cut s` is "
             "proxy and cut.\n")
    rows = cut_rows(knit, names)
    p.append(table(["mesh", "input faces", "proxy", "proxy faces", "irregular vertices",
                    "singular vertices", "cut edges", "arcs", "overlapping faces", "cut s"],
                   ["---", "---:", "---", "---:", "---:", "---:", "---:", "---:", "---:", "---:"],
                   rows))
    p.append("")
    p.append(f"Totals over the {len(rows)} cuts: {thousands(sum(r[7] for r in rows))} arcs, "
             f"{thousands(sum(r[6] for r in rows))} cut edges.\n")

    p.append("### Stitch mesh (§6)\n")
    p.append("Stitch faces by type; the share of stitches with a side on the sheet's boundary; "
             "course and wale side lengths as mean / target and the share within 15% of it; "
             "stitches against the estimate area / (course × wale); the counts of the four "
             "rules of thumb (edge, stacked and opposed shaping, one-stitch rows); the targets "
             "the mesh misses (means within 1 ± 0.05, shares at least 90%, stitches within "
             "1 ± 0.10: docs/stitch-mesh.md); stitches with a side more than one wale off the "
             "surface (P087); how far the stitch vertices lie from the garment's surface, the "
             "largest and the mean (`surface_distance`, docs/stitch-mesh.md, \"On the garment's "
             "surface\").\n")
    rows, met, far = stitch_rows(knit, names)
    p.append(table(["mesh"] + stitch_mesh_table.HEADER
                   + ["off surface", "from the garment, max / mean mm", "s"],
                   ["---"] + stitch_mesh_table.ALIGN + ["---:", "---:", "---:"], rows))
    p.append("")
    p.append(f"{met} of {len(rows)} stitch meshes meet every target; "
             f"{thousands(sum(int(r[1]) for r in rows))} stitches in all. The stitch vertices "
             f"lie within half a wale of the garment on {len(rows) - len(far)} of {len(rows)}"
             + (" (not: " + ", ".join(far) + ")" if far else "") + ".\n")

    p.append("### Schedule (§7)\n")
    p.append("Pieces; scheduling cuts (§7.3); wale seams (rows that meet running opposite ways, "
             "left open to sew); patches moved and loops set aside by the order search "
             "(docs/scheduling.md); the widest piece in needles (the machine has 540); "
             "carriage passes and transfers over all pieces; the VM's warnings (every piece "
             "has passed the VM with no error, or the stage would have failed); `s` is the "
             "stage's own time, `branch s` the wall time of the three commands.\n")
    rows = schedule_rows(knit, names, wall)
    p.append(table(["mesh", "pieces", "schedule cuts", "wale seams", "patches moved",
                    "loops set aside", "widest", "passes", "transfers", "VM warnings",
                    "est. knit time", "s", "branch s"],
                   ["---"] + ["---:"] * 12, rows))
    p.append("")
    no_cut = sum(1 for r in rows if r[2] == 0)
    meshes = "1 mesh" if len(rows) == 1 else f"{len(rows)} meshes"
    p.append(f"{meshes} scheduled: {plural(sum(r[1] for r in rows), 'piece')}, "
             f"{plural(sum(r[2] for r in rows), 'scheduling cut')}; {no_cut} of them need no "
             "scheduling cut.\n")

    # The paper's covers.
    p.append("## The paper's covers\n")
    p.append("The quad-dominant meshes of the paper's examples (§8), from the knit branch above, "
             "plain, and the same stitch meshes scheduled again with `--pattern seed`. The paper "
             "knits its bunny in 16 min plain and 33 min seed, and Fertility \"without any "
             "additional cuts\" from scheduling; it gives no figure per stage but \"a few "
             "minutes\" for cutting, stitch meshing and scheduling together.\n")
    rows = []
    for name in PAPER_COVERS:
        plain = schedule_figures(os.path.join(knit, name))
        seed = schedule_figures(os.path.join(out, "seed", name))
        stitch = load(os.path.join(knit, name, "stitch-mesh.json"))
        if plain is None or seed is None or stitch is None:
            continue
        rows.append([name, thousands(stitch["report"]["faces"]["total"]), plain["pieces"],
                     plain["cuts"], f"{thousands(plain['passes'])} / {thousands(seed['passes'])}",
                     f"{thousands(plain['transfers'])} / {thousands(seed['transfers'])}",
                     f"{minutes(plain['knit_time_s'])} / {minutes(seed['knit_time_s'])}"])
    p.append(table(["cover", "stitches", "pieces", "schedule cuts", "passes plain / seed",
                    "transfers plain / seed", "est. knit time plain / seed"],
                   ["---", "---:", "---:", "---:", "---:", "---:", "---:"], rows))
    p.append("")

    # Whole plans.
    p.append("## Whole plans\n")
    plans = sorted(d for d in os.listdir(os.path.join(run, "plan"))
                   if os.path.isdir(os.path.join(run, "plan", d)))
    p.append("`wearknit plan MESH --wearer MESH --size-mm 100` (the garment over itself) for "
             + ", ".join(f"`{n}`" for n in plans)
             + ", and `wearknit demo` (an egg-like ellipsoid 50 × 50 × 90 mm covered by the "
             "same shape 1.5 mm further out, docs/plan.md); "
             "every option at its default. The wearability stage runs beside the stitch mesh "
             "and the schedule, so the total is less than the sum of the stages.\n")
    folders = [(n, os.path.join(run, "plan", n)) for n in plans]
    folders.append(("demo", os.path.join(run, "demo")))
    args = []
    for name, folder in folders:
        label = "demo" if name == "demo" else "plan/" + name
        args.append("%s=%s:%d:%.0f" % (name, folder, failed.get(label, 0), wall.get(label, 0)))
    p.append(plan_table(args))
    p.append("")
    p.append("The wearability stage of these plans: cut-arcs, how many were sewn and laced, the "
             "strip-off tests run (docs/wearability.md: runs of arcs are tested together), the "
             "cloth steps of the recorded trials, and whether the proxy had to be cut again "
             "(§5).\n")
    p.append(table(["plan", "arcs", "sewn", "laced", "tests", "cloth steps", "re-cut", "s"],
                   ["---", "---:", "---:", "---:", "---:", "---:", "---", "---:"],
                   wearability_rows(folders)))
    p.append("")
    p.append("Whole plans of the other shared meshes take from seconds to minutes each on two "
             "cores and are not part of this run; `bench/plan_all.sh` (every closed mesh over "
             "itself, \"Whole plans of the 28 closed meshes\" below) and "
             "`bench/plan_results.sh` (the paper's covers over their objects) measure them.")
    print("\n".join(p))


if __name__ == "__main__":
    if len(sys.argv) != 5:
        print(__doc__.strip(), file=sys.stderr)
        sys.exit(2)
    main(*sys.argv[1:])
