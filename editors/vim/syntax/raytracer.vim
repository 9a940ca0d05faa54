" Scene files of the raytracer: syntax highlighting (docs/editors.md).
"
" The tokens of grammar/scene.ebnf: a word is any run of characters other
" than white space, `#` and `"`; a comment runs from `#` to the end of the
" line; a string is double-quoted on one line with `\"` and `\\` escapes.
" Section keywords link to Keyword, attribute names to Identifier, numbers
" to Number, strings and texture paths to String, comments to Comment, and
" an unterminated string to Error.

if exists('b:current_syntax')
  finish
endif

" Word characters as the language has them: all but space, `"` and `#`,
" so `sphere1` or `color.` is one word and no keyword.
syntax iskeyword 33,36-255
syntax case match

syntax keyword raytracerSection camera sphere plane light
syntax keyword raytracerAttribute dimension center color reflectivity normal headup location
" The value of `texture` is a path: a bare word (or a string).
syntax keyword raytracerAttribute texture nextgroup=raytracerPath,raytracerString skipwhite skipnl
syntax match raytracerPath /[^[:space:]#"]\+/ contained

" A whole word that reads as a number: sign, digits with an optional
" fraction (or a fraction alone), and an optional exponent.
syntax match raytracerNumber /\S\@<![-+]\=\%(\d\+\%(\.\d*\)\=\|\.\d\+\)\%([eE][-+]\=\d\+\)\=\%([[:space:]#"]\|$\)\@=/

" An unterminated string runs to the end of the line; a closed one, defined
" after it, wins where the closing quote is there.
syntax match raytracerStringError /"\%([^"\\]\|\\.\)*$/
syntax region raytracerString start=/"/ skip=/\\[\\"]/ end=/"/ oneline

syntax match raytracerComment /#.*$/ contains=@Spell

highlight default link raytracerSection Keyword
highlight default link raytracerAttribute Identifier
highlight default link raytracerNumber Number
highlight default link raytracerString String
highlight default link raytracerPath String
highlight default link raytracerStringError Error
highlight default link raytracerComment Comment

let b:current_syntax = 'raytracer'
