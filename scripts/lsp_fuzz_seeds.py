#!/usr/bin/env python3
"""Write the seeds of the `lsp` fuzz target (fuzz/seeds/lsp/).

The target decodes its input with the `arbitrary` crate (1.x), so a seed is
the encoding of an initial text and batches of changes in that crate's
layout: a string's bytes come from the front and its length byte from the
end (each seed stays under 256 bytes, so every length is one byte); a batch
is its change count minus one, then per change a byte that is 0 for a
whole-text replacement (else 1), the four position bytes (line and column of
the start, then of the end; 255 stands for u32::MAX) and the new text.

Usage: scripts/lsp_fuzz_seeds.py  (rewrites the seeds it names)
"""

import os

MAX = 255  # decoded as u32::MAX

# name: (initial text, [batch, ...]); a change is (start, end, text) with
# start and end (line, column) pairs, or (None, None, text) for a whole text.
SEEDS = {
    "type_a_sphere": (
        "camera 4\n",
        [[((1, 0), (1, 0), "sphere\n")], [((2, 0), (2, 0), "  dimension 1\n")]],
    ),
    "delete_across_crlf": (
        "camera 4\r\nsphere\r\n  dimension 1\r\n",
        [[((0, 8), (1, 0), " "), ((1, 3), (2, 2), "")]],
    ),
    "emoji_columns": (
        "# 😀 é\nsphere texture \"😀.ppm\"\n",
        [[((0, 3), (0, 4), "x"), ((1, 16), (1, 18), "ü")]],
    ),
    "past_the_end": (
        "camera 4\rsphere",
        [[((9, 9), (MAX, MAX), "light"), ((0, MAX), (0, 2), "\n")]],
    ),
    "replace_whole_text": (
        "camera 4\n",
        [[(None, None, "sphere center 0 0 -5\n"), ((0, 7), (0, 20), "dimension 1")]],
    ),
}


def encode(text, batches):
    front, back = bytearray(), []

    def string(s):
        data = s.encode()
        front.extend(data)
        back.append(len(data))

    string(text)
    for batch in batches:
        assert 1 <= len(batch) <= 4
        front.append(len(batch) - 1)
        for start, end, new in batch:
            if start is None:
                front.append(0)
            else:
                front.append(1)
                front.extend([*start, *end])
            string(new)
    data = bytes(front) + bytes(reversed(back))
    assert len(data) <= 256, "a longer seed needs two-byte lengths"
    return data


if __name__ == "__main__":
    folder = os.path.join(os.path.dirname(__file__), "..", "fuzz", "seeds", "lsp")
    os.makedirs(folder, exist_ok=True)
    for name, (text, batches) in SEEDS.items():
        with open(os.path.join(folder, name), "wb") as f:
            f.write(encode(text, batches))
