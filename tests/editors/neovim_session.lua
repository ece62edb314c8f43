-- Neovim's side of tests/editors/test_neovim.py, run headless (`nvim --headless --clean`).
-- Reads its orders from the JSON file named by $SCRIPTC_EDITOR_TEST: opens the file,
-- starts `scriptc lsp` on it offering every position encoding (or, with `documented`, sets
-- Neovim 0.11 up as docs/editors.md says and lets it start the server), makes each edit
-- through Neovim's own buffer API (so Neovim computes the protocol's ranges), then rewrites
-- the configuration (unless `config_later` is empty); after the opening and after each step it waits
-- until the diagnostics change and records the buffer's lines and its diagnostics (columns in
-- bytes, as Neovim keeps them), and the buffer's filetype and comment string. Writes the
-- record to the result file and quits (status 1 on a Lua error).
local setup = vim.fn.json_decode(table.concat(vim.fn.readfile(os.getenv("SCRIPTC_EDITOR_TEST")), "\n"))
local record = { steps = {} }

local function diagnostics(bufnr)
  local out = {}
  for _, d in ipairs(vim.diagnostic.get(bufnr)) do
    table.insert(out, { code = d.code, message = d.message, line = d.lnum, column = d.col,
                        end_line = d.end_lnum, end_column = d.end_col })
  end
  table.sort(out, function(a, b)
    if a.line ~= b.line then return a.line < b.line end
    if a.column ~= b.column then return a.column < b.column end
    return a.message < b.message
  end)
  return out
end

-- docs/editors.md, "Neovim" (0.11 and newer), with the test's command.
local function documented()
  vim.filetype.add({
    extension = { script = "scriptc" },
    pattern = { [".*%.test%.toml"] = "toml.scriptc-test" },
  })
  vim.lsp.config("scriptc", {
    cmd = setup.cmd,
    filetypes = { "scriptc", "toml.scriptc-test" },
    root_markers = { "scriptc.toml", "pyproject.toml", ".git" },
  })
  vim.lsp.enable("scriptc")
end

local function start(bufnr)
  local capabilities = vim.lsp.protocol.make_client_capabilities()
  capabilities.general = capabilities.general or {}
  capabilities.general.positionEncodings = { "utf-8", "utf-16", "utf-32" }
  local config = {
    name = "scriptc",
    cmd = setup.cmd,
    root_dir = setup.root,
    capabilities = capabilities,
    on_init = function(client, result)
      record.position_encoding = result.capabilities.positionEncoding
      -- Neovim 0.10 and newer count in the server's `positionEncoding` by themselves;
      -- older ones in `offset_encoding`, which can be set here only.
      if vim.fn.has("nvim-0.10") == 0 then
        client.offset_encoding = result.capabilities.positionEncoding or "utf-16"
      end
    end,
  }
  if vim.lsp.start then
    vim.lsp.start(config, { bufnr = bufnr })
  else -- Neovim 0.7
    vim.lsp.buf_attach_client(bufnr, vim.lsp.start_client(config))
  end
end

local function run()
  if setup.documented then
    documented()
  end
  vim.cmd("edit " .. vim.fn.fnameescape(setup.file))
  local bufnr = vim.api.nvim_get_current_buf()
  record.filetype = vim.bo[bufnr].filetype
  record.commentstring = vim.bo[bufnr].commentstring
  if not setup.documented then
    start(bufnr)
  end

  local function step(name, act)
    local before = vim.fn.json_encode(diagnostics(bufnr))
    act()
    local changed = vim.wait(setup.timeout_ms, function()
      return vim.fn.json_encode(diagnostics(bufnr)) ~= before
    end, 20)
    table.insert(record.steps, { name = name, changed = changed,
                                 lines = vim.api.nvim_buf_get_lines(bufnr, 0, -1, true),
                                 diagnostics = diagnostics(bufnr) })
  end

  step("open", function() end)
  for n, edit in ipairs(setup.edits) do
    step("edit " .. n, function()
      vim.api.nvim_buf_set_text(bufnr, edit.line, edit.start_byte, edit.line, edit.end_byte,
                                vim.split(edit.new_text, "\n", { plain = true }))
    end)
  end
  if setup.config_later ~= "" then
    step("configuration", function()
      vim.fn.writefile(vim.split(setup.config_later, "\n", { plain = true }), setup.config)
    end)
  end
  for _, client in ipairs((vim.lsp.get_clients or vim.lsp.get_active_clients)()) do
    record.offset_encoding = client.offset_encoding
  end
end

local ok, err = pcall(run)
if not ok then
  record.error = tostring(err)
end
vim.fn.writefile({ vim.fn.json_encode(record) }, setup.result)
vim.cmd(ok and "qall!" or "cquit 1")
