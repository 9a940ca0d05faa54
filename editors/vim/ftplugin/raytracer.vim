" Scene files of the raytracer: comments, word characters and indentation
" (docs/editors.md).

if exists('b:did_ftplugin')
  finish
endif
let b:did_ftplugin = 1

" A comment runs from `#` to the end of its line.
setlocal commentstring=#\ %s
setlocal comments=:#
setlocal formatoptions-=t formatoptions+=croql
" The layout `raytracer fmt` writes: attributes two spaces in.
setlocal expandtab shiftwidth=2 softtabstop=2

let b:undo_ftplugin = 'setlocal commentstring< comments< formatoptions< expandtab< shiftwidth< softtabstop<'
