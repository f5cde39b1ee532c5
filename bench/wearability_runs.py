"""Reads the rows of bench/wearability_pairs.sh (NAME:MODE:FOLDER:WALL): per
mesh and mode, the summary of its wearability.json (None when the run left
none) and its wall seconds."""
import json


def runs_of(rows):
    runs = {}
    for row in rows:
        name, mode, folder, wall = row.split(":")
        try:
            with open(folder + "/wearability.json") as f:
                summary = json.load(f)["summary"]
        except (OSError, ValueError):
            summary = None
        runs.setdefault(name, {})[mode] = (summary, float(wall))
    return runs
