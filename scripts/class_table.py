#!/usr/bin/env python3
"""The closing table of a class graded by `raytracer grade --class`.

Usage: scripts/class_table.py [--into FILE] REPORT [REPORT...]

For each student of each REPORT folder (its REPORT/<student>/summary.json),
one Markdown row: the class (the report folder's name), the student, the
aspects that lost points with the scenes where they did, and the score.
Aspects that fail on a scene carrying no points (a robustness scene) are
left out: they cost nothing. With --into, the table replaces the one that
follows the line `<!-- class table: scripts/class_table.py -->` in FILE
(`make class-table` writes docs/grading.md's so); else it is printed.
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


MARKER = "<!-- class table: scripts/class_table.py -->"


def table(reports):
    lines = [
        "| class | student | aspects that lost points (scenes) | score |",
        "|---|---|---|---|",
    ]
    for report in reports:
        name = os.path.basename(os.path.normpath(report))
        for student, words, score, top in rows(report):
            lines.append(f"| {name} | `{student}` | {words} | {score:g} / {top:g} |")
    return lines


def write_into(path, lines):
    with open(path, encoding="utf-8") as f:
        text = f.read().split("\n")
    start = text.index(MARKER) + 1
    end = start
    while end < len(text) and text[end].startswith("|"):
        end += 1
    text[start:end] = lines
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(text))


def main():
    args = sys.argv[1:]
    into = None
    if args[:1] == ["--into"] and len(args) >= 2:
        into, args = args[1], args[2:]
    if not args:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    lines = table(args)
    if into:
        write_into(into, lines)
    else:
        print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
