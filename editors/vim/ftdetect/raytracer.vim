" Scene files of the raytracer: file type detection (docs/editors.md).
"
" A scene is detected by its content, not only by its name, since scenes are
" commonly plain `.txt` files: `*.scene` is always a scene, and a `*.txt`
" file is one when its first word that is not in a comment is a section
" keyword in any case (`camera`, `Camera`, `SPHERE`, …), the way every scene
" starts. Other `.txt` files keep the `text` file type.
"
" `set filetype` rather than `setfiletype`: the runtime's own rule has
" already made every `.txt` file `text` by the time this one runs.

function! s:StartsLikeScene() abort
  " The first line that is neither blank nor a comment, within the first
  " hundred (a header comment is seldom longer).
  for line in getline(1, 100)
    if line =~# '^\s*\%(#.*\)\=$'
      continue
    endif
    return line =~? '^\s*\%(camera\|sphere\|plane\|light\)\%(\s\|#\|$\)'
  endfor
  return 0
endfunction

autocmd BufNewFile,BufRead *.scene setfiletype raytracer
autocmd BufRead *.txt if s:StartsLikeScene() | set filetype=raytracer | endif
