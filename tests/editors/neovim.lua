-- End-to-end: Neovim's built-in LSP client drives `raytracer lsp` on a
-- scene with mistakes. Run by tests/neovim.rs as
--   RAYTRACER=<binary> SCENE=<file> nvim --headless --clean -c 'luafile tests/editors/neovim.lua'
-- It waits for the diagnostics and prints them, applies the quick fix
-- "project `headup` onto the plane", formats the buffer, writes the file
-- and shuts the server down. Any failure exits non-zero (`cquit`).
-- Written for Neovim 0.7 (Debian's) and later: `vim.lsp.start_client`,
-- `formatting_sync` where `format` is missing.

local function fail(message)
  io.stderr:write("neovim.lua: " .. message .. "\n")
  vim.cmd("cquit 1")
end

local function run()
  local bin = assert(os.getenv("RAYTRACER"), "RAYTRACER is unset")
  local scene = assert(os.getenv("SCENE"), "SCENE is unset")
  vim.cmd("edit " .. vim.fn.fnameescape(scene))
  local buf = vim.api.nvim_get_current_buf()
  local client_id = vim.lsp.start_client({
    name = "raytracer",
    cmd = { bin, "lsp", "--debounce-ms", "50" },
    root_dir = vim.fn.fnamemodify(scene, ":h"),
  })
  if not client_id then
    return fail("the server did not start")
  end
  vim.lsp.buf_attach_client(buf, client_id)

  if not vim.wait(10000, function() return #vim.diagnostic.get(buf) > 0 end, 20) then
    return fail("no diagnostics within 10 s")
  end
  for _, d in ipairs(vim.diagnostic.get(buf)) do
    local code = d.code or (d.user_data and d.user_data.lsp and d.user_data.lsp.code) or "?"
    io.stdout:write(string.format("diagnostic %d:%d %s %s\n", d.lnum + 1, d.col + 1, code,
      vim.split(d.message, "\n")[1]))
  end

  local client = vim.lsp.get_client_by_id(client_id)
  local headup_line
  for i, line in ipairs(vim.api.nvim_buf_get_lines(buf, 0, -1, false)) do
    if line:find("headup") then headup_line = i - 1 end
  end
  local response = client.request_sync("textDocument/codeAction", {
    textDocument = { uri = vim.uri_from_bufnr(buf) },
    range = { start = { line = headup_line, character = 0 }, ["end"] = { line = headup_line, character = 0 } },
    context = { diagnostics = {} },
  }, 5000, buf)
  if not response or response.err then
    return fail("codeAction failed: " .. vim.inspect(response))
  end
  local applied = false
  for _, action in ipairs(response.result or {}) do
    io.stdout:write(string.format("action %s: %s\n", action.kind, action.title))
    if action.kind == "quickfix" and action.title:find("headup") and not applied then
      vim.lsp.util.apply_workspace_edit(action.edit, client.offset_encoding)
      applied = true
    end
  end
  if not applied then
    return fail("no quick fix for the headup")
  end

  if vim.lsp.buf.format then
    vim.lsp.buf.format({ timeout_ms = 5000, bufnr = buf })
  else
    vim.lsp.buf.formatting_sync(nil, 5000)
  end
  vim.cmd("write")
  io.stdout:write("formatted and written\n")

  vim.lsp.stop_client(client_id)
  vim.wait(5000, function() return vim.lsp.get_client_by_id(client_id) == nil end, 20)
  vim.cmd("qall!")
end

local ok, err = pcall(run)
if not ok then
  fail(tostring(err))
end
