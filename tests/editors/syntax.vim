" The Vim syntax of editors/vim/ in a real editor: run by tests/vim_syntax.rs
" in headless Neovim and in Vim, with only editors/vim/ (and the editor's own
" runtime) on the runtime path:
"   RAYTRACER_VIM=editors/vim SCENE=a.txt PLAIN=b.txt PROBES='1:1 2:8' OUT=out \
"     nvim --headless -u NONE -i NONE -n -S tests/editors/syntax.vim
" It writes to $OUT the file type of each file (CAPITAL a scene whose
" keyword is written `Camera`), the scene's commentstring,
" and at each probe `LINE:COL` the syntax group there, the group that links
" to, and where the links end (`synIDtrans`). Any error exits non-zero.

function! s:Linked(name) abort
  if a:name ==# '-'
    return '-'
  endif
  let found = matchlist(execute('highlight ' . a:name), 'links to \(\w\+\)')
  return empty(found) ? '-' : found[1]
endfunction

function! s:Run() abort
  let &runtimepath = $RAYTRACER_VIM . ',' . $VIMRUNTIME
  filetype plugin on
  syntax on
  let out = []
  execute 'edit ' . fnameescape($PLAIN)
  call add(out, 'plain filetype ' . &filetype)
  execute 'edit ' . fnameescape($CAPITAL)
  call add(out, 'capital filetype ' . &filetype)
  execute 'edit ' . fnameescape($SCENE)
  call add(out, 'scene filetype ' . &filetype)
  call add(out, 'commentstring ' . &commentstring)
  for probe in split($PROBES)
    let [line, col] = map(split(probe, ':'), 'str2nr(v:val)')
    let id = synID(line, col, 1)
    let name = synIDattr(id, 'name')
    let group = name ==# '' ? '-' : name
    let final = synIDattr(synIDtrans(id), 'name')
    call add(out, printf('%s %s %s %s', probe, group, s:Linked(group),
          \ final ==# '' ? '-' : final))
  endfor
  call writefile(out, $OUT)
endfunction

try
  call s:Run()
  qall!
catch
  call writefile(['error: ' . v:exception . ' at ' . v:throwpoint], $OUT)
  cquit!
endtry
