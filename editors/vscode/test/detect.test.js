// The `.txt` detection of detect.js, under node's test runner.

"use strict";

const test = require("node:test");
const assert = require("node:assert");
const { startsLikeScene } = require("../detect");

test("a scene after a header comment and blank lines", () => {
  assert.ok(startsLikeScene("# The seed sample.\n#\n\ncamera 400\nsphere\n"));
  assert.ok(startsLikeScene("  light location 0 5 0 color 1 1 1"));
  assert.ok(startsLikeScene("\r\n# crlf\r\nsphere# a comment touching it\r\n"));
  assert.ok(startsLikeScene("plane"));
});

test("text that is no scene", () => {
  assert.ok(!startsLikeScene(""));
  assert.ok(!startsLikeScene("# only a comment\n\n"));
  assert.ok(!startsLikeScene("Some notes\ncamera 400\n"));
  assert.ok(!startsLikeScene("spheres of influence\n"));
  assert.ok(!startsLikeScene("Camera 400\n"));
});

test("the first word is looked for in the first hundred lines only", () => {
  assert.ok(startsLikeScene("#\n".repeat(99) + "camera 1\n"));
  assert.ok(!startsLikeScene("#\n".repeat(100) + "camera 1\n"));
});
