#!/usr/bin/env python3
"""The sweep's table for docs/results.md from one or more sweep.tsv files
(bench/sweep.sh): per size, the runs, those that passed, the failures by
stage and code, internal errors; then every failure with its message.
    bench/sweep_table.py OUT/sweep.tsv [MORE.tsv ...] > table.md"""
import collections
import sys

rows = []
for path in sys.argv[1:]:
    rows += [l.rstrip("\n").split("\t") for l in open(path) if l.strip()]
sizes = sorted({(r[4] == "plan", int(r[2])) for r in rows})
print("| run | seeds | runs | ok | failed (stage code: count) | internal errors | pieces | pieces the VM rejects |")
print("| --- | --- | ---: | ---: | --- | ---: | ---: | ---: |")
for plan, size in sizes:
    group = [r for r in rows if int(r[2]) == size and (r[4] == "plan") == plan]
    seeds = " ".join(sorted({r[1] for r in group}, key=int))
    failed = collections.Counter(f"{r[4]} {r[5]}" for r in group if r[3] != "ok")
    kind = f"whole plan, {size} mm" if plan else f"knit branch, {size} mm"
    print(f"| {kind} | {seeds} | {len(group)} | {sum(r[3] == 'ok' for r in group)} | "
          f"{', '.join(f'{k}: {n}' for k, n in sorted(failed.items())) or '—'} | "
          f"{sum(r[3] == 'internal' for r in group)} | "
          f"{sum(int(r[7]) for r in group if r[3] == 'ok')} | {sum(int(r[8]) for r in group)} |")
failures = [r for r in rows if r[3] != "ok"]
if failures:
    print()
    print("| mesh | seed | size mm | stage | code | message |")
    print("| --- | ---: | ---: | --- | --- | --- |")
    for r in sorted(failures, key=lambda r: (r[0], int(r[2]), int(r[1]))):
        message = r[10].split(": error: ", 1)[-1].replace("|", "\\|")
        print(f"| {r[0]} | {r[1]} | {r[2]} | {r[4]} | {r[5]} | {message} |")
