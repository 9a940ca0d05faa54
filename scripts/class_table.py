#!/usr/bin/env python3
"""The closing table of a class graded by `raytracer grade --class`.

Usage: scripts/class_table.py REPORT [REPORT...]

For each student of each REPORT folder (its REPORT/<student>/summary.json),
one Markdown row: the class (the report folder's name), the student, the
aspects that lost points with the scenes where they did, and the score.
Aspects that fail on a scene carrying no points (a robustness scene) are
left out: they cost nothing.
"""

import json
import os
import sys


def rows(report):
    for student in sorted(os.listdir(report)):
        path = os.path.join(report, student, "summary.json")
        if not os.path.isfile(path):
            continue
        with open(path, encoding="utf-8") as f:
            summary = json.load(f)
        lost = {}
        for scene in summary["scenes"]:
            if scene.get("status") not in ("match", "differs"):
                lost.setdefault(scene.get("status"), []).append(scene["scene"])
                continue
            for aspect in scene.get("aspects") or []:
                if not aspect["pass"] and aspect["points"] > 0:
                    lost.setdefault(aspect["aspect"], []).append(scene["scene"])
        words = "; ".join(
            f"{aspect} ({', '.join(sorted(scenes))})" for aspect, scenes in sorted(lost.items())
        )
        yield student, words or "none", summary["score"], summary["max_score"]


def main():
    if len(sys.argv) < 2:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    print("| class | student | aspects that lost points (scenes) | score |")
    print("|---|---|---|---|")
    for report in sys.argv[1:]:
        name = os.path.basename(os.path.normpath(report))
        for student, words, score, top in rows(report):
            print(f"| {name} | `{student}` | {words} | {score:g} / {top:g} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
