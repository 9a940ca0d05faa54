// Whether a `.txt` file is a scene: its first line that is neither blank
// nor a comment starts with a section keyword, as every scene does (the
// rule of editors/vim/ftdetect/raytracer.vim). Kept apart from
// extension.js so node's test runner can load it without VS Code.

"use strict";

/** How many lines to look through for the first word (a header comment is seldom longer). */
const LINES = 100;

const COMMENT_OR_BLANK = /^\s*(#.*)?$/;
const SECTION_START = /^\s*(camera|sphere|plane|light)(\s|#|$)/;

/**
 * @param {string} text the start of the file (more is ignored)
 * @returns {boolean}
 */
function startsLikeScene(text) {
  for (const line of text.split(/\r\n|\r|\n/, LINES)) {
    if (!COMMENT_OR_BLANK.test(line)) {
      return SECTION_START.test(line);
    }
  }
  return false;
}

module.exports = { startsLikeScene };
