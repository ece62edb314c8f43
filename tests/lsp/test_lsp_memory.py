"""A long session keeps the server's memory flat: quick edits (each analysed, with no idle
time for the collector, which the server runs only when idle) neither retain anything per
edit nor leave reference cycles behind.

The session runs in a child process that drives the server's own protocol object in
process, as `serve` sets it up (the collector off), and reports, over a stretch of edits
after a warm-up: the objects still alive that were not before (what the session retains per
edit: before the fix, pygls's futures of notifications, 1.4 KiB a keystroke) and the objects
a full collection frees (the reference cycles made per edit: before the fix, the converter of
each change's text, and the traceback of each cached syntax error with the frames and items
it held). Figures of the whole server over stdio: `bench/bench_lsp.py --memory`.
"""

from __future__ import annotations

import json
import subprocess
import sys

DRIVER = r'''
import gc, json, sys

from scriptc.server import main

EDITS = int(sys.argv[1])
server = main.SERVER


class Sink:
    def write(self, data):
        pass

    def close(self):
        pass


server.protocol.set_writer(Sink())
gc.disable()  # as `serve` runs the server
next_id = 0


def send(method, params, request=False):
    global next_id
    message = {"jsonrpc": "2.0", "method": method, "params": params}
    if request:
        next_id += 1
        message["id"] = next_id
    server.protocol.handle_message(server.protocol.structure_message(message))


lines = ["% Un'attività di prova: è lunga %", "[prova]", "[goal:g]", "  [action]"]
for i in range(0, 120, 2):
    lines.append(f'    [b#blk{i}#blk_inst: MV("0.{i % 10}, 0, 0.5, 0, 1000") '
                 f'LD("1, 0, 0, 1, 0, 500") AO("canzone_{i}.wav, 0, 1000")] % più 😀 %')
    lines.append(f"    [b#jmp{i}#blk_jump: CND(! {{E: gt(@count, {i})}}) "
                 f"TRJMP(blk{i + 2 if i + 2 < 120 else i}) FLSJMP()]")
lines.append("    [b#blk120#blk_terminus]")
text = "\n".join(lines) + "\n"
uri = "file:///memory/long.script"
send("initialize", {"processId": None, "rootUri": None, "capabilities": {
    "general": {"positionEncodings": ["utf-8", "utf-16"]}}}, request=True)
send("initialized", {})
send("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": "scriptc",
                                               "version": 1, "text": text}})

anchors = [n for n, line in enumerate(lines) if 'MV("0.' in line]
version = 1


def edit(n):
    """A keystroke in a speed, then its deletion; every fourth block, a `)` deleted and
    typed back (a syntax error, then its repair). Lines keep their length in between."""
    global version
    line = anchors[(n // 2) % len(anchors)]
    column = len(lines[line][:lines[line].index('MV("0.') + 6].encode())
    if (n // 2) % 4 == 3:
        column = len(lines[line][:lines[line].index(")")].encode())
        change = ("", column, column + 1) if n % 2 == 0 else (")", column, column)
    else:
        change = ("5", column, column) if n % 2 == 0 else ("", column, column + 1)
    new, start, end = change
    version += 1
    send("textDocument/didChange", {
        "textDocument": {"uri": uri, "version": version},
        "contentChanges": [{"range": {"start": {"line": line, "character": start},
                                      "end": {"line": line, "character": end}}, "text": new}]})
    if n % 10 == 0:  # requests too: their futures are pygls's to drop
        send("textDocument/diagnostic", {"textDocument": {"uri": uri}}, request=True)
        send("textDocument/hover", {"textDocument": {"uri": uri},
                                    "position": {"line": line, "character": 6}}, request=True)


def settle():
    gc.unfreeze()
    freed = gc.collect()
    gc.freeze()
    return freed


for n in range(200):  # warm-up: caches filled, lazy imports done
    edit(n)
settle()
alive = len(gc.get_objects()) + gc.get_freeze_count()
for n in range(200, 200 + EDITS):
    edit(n)
freed = settle()
grown = len(gc.get_objects()) + gc.get_freeze_count() - alive
futures = len(server.protocol._request_futures)
print(json.dumps({"freed": freed, "grown": grown, "futures": futures}))
'''

EDITS = 400


def test_quick_edits_retain_nothing_and_make_no_cycles():
    done = subprocess.run([sys.executable, "-c", DRIVER, str(EDITS)], capture_output=True,
                          text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stderr[-3000:]
    figures = json.loads(done.stdout.strip().splitlines()[-1])
    assert figures["futures"] == 0
    # Per edit: nothing retained, no cycle (a few objects of slack for the caches' churn:
    # a leak of one object per edit would already be 400).
    assert figures["grown"] < 50, figures
    assert figures["freed"] < 50, figures
