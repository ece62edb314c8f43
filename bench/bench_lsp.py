"""Language-server figures, through a real client over stdio (`scriptc lsp` as a subprocess).

On a script of about 90 KB (`generate.big_script`), after the server has opened it:

- **edit -> diagnostics**: the time from sending a `textDocument/didChange` that edits one
  block to receiving the `textDocument/publishDiagnostics` for that version. The edits type
  into and delete from a number of one block, at blocks spread over the whole file (an edit
  near the top moves every item after it, the costly case; near the end, the cheap one), and
  alternate with edits that break and repair a block (a syntax error and back). Target:
  median <= 60 ms.
- **completion** (labels inside `TRJMP(`, the longest list: every label of the script) and
  **hover** (on a block, on a label, on a function): request sent to response received.
  Target: <= 20 ms.

`--memory` measures a long session instead: the server's resident memory (RSS, from
/proc) after opening a script of about 20 KB, and again after 2,000 quick edits (each
awaiting its diagnostics, with no idle time between them: a fast typist, a replayed macro),
typed at places spread over the file, with a hover and the inlay hints asked after every
fourth edit (as editors ask after a change). Target: flat (no growth per edit).

The client is a minimal JSON-RPC client written here (asyncio pipes, no pygls), so the times
are the server's and the pipe's, not a Python client's decoding. `--pygls` measures through
pytest-lsp's client instead (what the tests use), for comparison.

Run: `.venv/bin/python bench/bench_lsp.py [--blocks N] [--rounds N] [--pygls] [--profile FILE]`
or `.venv/bin/python bench/bench_lsp.py --memory [--edits N]`
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from generate import big_script

SERVER = [sys.executable, "-m", "scriptc", "lsp"]
URI = "file:///bench/big.script"


class RawClient:
    """Just enough of an LSP client: requests with ids, notifications, and a reader task that
    files responses and notifications as they arrive, stamped with their arrival time."""

    def __init__(self, process: asyncio.subprocess.Process) -> None:
        self.process = process
        self.next_id = 0
        self.pending: dict[int, asyncio.Future] = {}
        self.published: dict[int, float] = {}  # version -> arrival time
        self.waiters: dict[int, asyncio.Future] = {}
        self.reader = asyncio.create_task(self._read())

    @classmethod
    async def start(cls, profile: str | None = None) -> RawClient:
        command = SERVER if profile is None else [
            sys.executable, "-m", "cProfile", "-o", profile, "-m", "scriptc", "lsp"]
        process = await asyncio.create_subprocess_exec(
            *command, stdin=asyncio.subprocess.PIPE, stdout=asyncio.subprocess.PIPE,
            stderr=sys.stderr, limit=2**24)
        return cls(process)

    def _send(self, message: dict) -> None:
        body = json.dumps(message).encode()
        self.process.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)

    async def _read(self) -> None:
        out = self.process.stdout
        while True:
            length = 0
            while True:
                line = await out.readline()
                if not line:
                    return
                if line.lower().startswith(b"content-length:"):
                    length = int(line.split(b":")[1])
                elif line in (b"\r\n", b"\n"):
                    break
            body = await out.readexactly(length)
            now = time.perf_counter()
            message = json.loads(body)
            if "id" in message and "method" not in message:
                future = self.pending.pop(message["id"], None)
                if future is not None and not future.done():
                    future.set_result((now, message))
            elif message.get("method") == "textDocument/publishDiagnostics":
                version = message["params"].get("version")
                self.published[version] = now
                waiter = self.waiters.pop(version, None)
                if waiter is not None and not waiter.done():
                    waiter.set_result(now)
            elif "id" in message:  # a request from the server: answer with nothing
                self._send({"jsonrpc": "2.0", "id": message["id"], "result": None})

    async def request(self, method: str, params: dict) -> tuple[float, dict]:
        """Send a request; returns (seconds until the response arrived, response)."""
        self.next_id += 1
        future = asyncio.get_running_loop().create_future()
        self.pending[self.next_id] = future
        sent = time.perf_counter()
        self._send({"jsonrpc": "2.0", "id": self.next_id, "method": method, "params": params})
        await self.process.stdin.drain()
        arrived, message = await future
        return arrived - sent, message

    def notify(self, method: str, params: dict) -> None:
        self._send({"jsonrpc": "2.0", "method": method, "params": params})

    async def diagnostics_after(self, method: str, params: dict, version: int) -> float:
        """Send a notification and wait for the diagnostics of `version`: seconds between."""
        waiter = asyncio.get_running_loop().create_future()
        self.waiters[version] = waiter
        sent = time.perf_counter()
        self.notify(method, params)
        await self.process.stdin.drain()
        arrived = await asyncio.wait_for(waiter, 60)
        return arrived - sent

    async def stop(self) -> None:
        await self.request("shutdown", None)
        self.notify("exit", None)
        await self.process.stdin.drain()
        await self.process.wait()
        self.reader.cancel()


def position(text: str, offset: int) -> dict:
    before = text[:offset]
    line = before.count("\n")
    column = before[before.rfind("\n") + 1:]
    return {"line": line, "character": len(column.encode("utf-16-le")) // 2}


def edits_for(text: str, rounds: int) -> list[tuple[int, int, str, str]]:
    """(start, end, new text, kind) edits, each one keystroke in one block, spread over the
    file: type a digit into a speed, delete it again (kind "typing": the script stays valid,
    so every check runs); every fourth block, delete a `)` and type it back (kind "syntax":
    a syntax error, then its repair)."""
    out = []
    anchors = [i for i in range(len(text)) if text.startswith('MV("0.', i)]
    step = max(1, len(anchors) // rounds)
    chosen = anchors[::step][:rounds]
    for n, at in enumerate(chosen):
        digit = at + len('MV("0.')
        if n % 4 == 3:
            close = text.index(")", at)
            out.append((close, close + 1, "", "syntax"))  # breaks the block: P002/P001
            out.append((close, close, ")", "syntax"))  # and repairs it
        else:
            out.append((digit, digit, "5", "typing"))  # a keystroke: 0.3 -> 0.53
            out.append((digit, digit + 1, "", "typing"))  # and back
    return out


async def bench(blocks: int, rounds: int, profile: str | None = None) -> dict:
    text = big_script(blocks)
    client = await RawClient.start(profile)
    capabilities = {"textDocument": {"completion": {"completionItem": {"snippetSupport": True}},
                                     "hover": {"contentFormat": ["markdown"]}}}
    started = time.perf_counter()
    await client.request("initialize", {"processId": os.getpid(), "rootUri": None,
                                        "capabilities": capabilities})
    client.notify("initialized", {})
    opened = await client.diagnostics_after("textDocument/didOpen", {"textDocument": {
        "uri": URI, "languageId": "scriptc", "version": 1, "text": text}}, 1)
    ready = time.perf_counter() - started

    version = 1
    edit_times: dict[str, list[float]] = {"typing": [], "syntax": []}
    cpu_before = cpu_seconds(client.process.pid)
    for start, end, new, kind in edits_for(text, rounds):
        rng = {"start": position(text, start), "end": position(text, end)}
        text = text[:start] + new + text[end:]
        version += 1
        edit_times[kind].append(await client.diagnostics_after("textDocument/didChange", {
            "textDocument": {"uri": URI, "version": version},
            "contentChanges": [{"range": rng, "text": new}]}, version))
    edits_cpu = (cpu_seconds(client.process.pid) - cpu_before) / (version - 1)

    doc = {"uri": URI}
    requests: dict[str, list[float]] = {"completion (labels in TRJMP)": [], "hover on a block": [],
                                        "hover on a label": [], "hover on a function": [],
                                        "completion (E: functions)": []}
    jumps = [i for i in range(len(text)) if text.startswith("TRJMP(", i)]
    calls = [i for i in range(len(text)) if text.startswith("E: gt(", i)]
    insts = [i for i in range(len(text)) if text.startswith("blk_inst:", i)]
    for n in range(rounds):
        j = jumps[n * len(jumps) // rounds] + len("TRJMP(")
        for name, offset, method in (
                ("completion (labels in TRJMP)", j, "textDocument/completion"),
                ("hover on a label", j + 1, "textDocument/hover"),
                ("hover on a block", insts[n * len(insts) // rounds] + 2, "textDocument/hover"),
                ("hover on a function", calls[n * len(calls) // rounds] + 4, "textDocument/hover"),
                ("completion (E: functions)", calls[n * len(calls) // rounds] + 3,
                 "textDocument/completion")):
            took, response = await client.request(method, {"textDocument": doc,
                                                           "position": position(text, offset)})
            assert response.get("result") is not None, (name, response)
            requests[name].append(took)
    took, response = await client.request("textDocument/completion", {
        "textDocument": doc, "position": position(text, jumps[0] + len("TRJMP("))})
    labels = len(response["result"]["items"])
    await client.stop()
    return {"size": len(text.encode()), "blocks": blocks, "ready": ready, "open": opened,
            "edits": edit_times, "requests": requests, "labels": labels, "edit_cpu": edits_cpu}


async def bench_pygls(blocks: int, rounds: int) -> dict:
    """The same edits and requests through pytest-lsp's client (pygls)."""
    from lsprotocol import types as lsp
    from pytest_lsp import ClientServerConfig

    sys.path.insert(0, str(Path(__file__).parent.parent / "tests" / "lsp"))
    from lsptest import capabilities, diagnostics_of, make_client

    text = big_script(blocks)
    client = await ClientServerConfig(server_command=SERVER, client_factory=make_client).start()
    await client.initialize_session(lsp.InitializeParams(capabilities=capabilities()))
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(URI, "scriptc", 1, text)))
    await diagnostics_of(client, URI, 1, 60)
    version = 1
    edit_times: dict[str, list[float]] = {"typing": [], "syntax": []}
    for start, end, new, kind in edits_for(text, rounds):
        rng = lsp.Range(lsp.Position(**position(text, start)), lsp.Position(**position(text, end)))
        text = text[:start] + new + text[end:]
        version += 1
        sent = time.perf_counter()
        client.text_document_did_change(lsp.DidChangeTextDocumentParams(
            lsp.VersionedTextDocumentIdentifier(uri=URI, version=version),
            [lsp.TextDocumentContentChangePartial(range=rng, text=new)]))
        await diagnostics_of(client, URI, version, 60)
        edit_times[kind].append(time.perf_counter() - sent)
    jumps = [i for i in range(len(text)) if text.startswith("TRJMP(", i)]
    requests: dict[str, list[float]] = {"completion (labels in TRJMP)": [], "hover on a label": []}
    for n in range(rounds):
        j = jumps[n * len(jumps) // rounds] + len("TRJMP(")
        p = lsp.Position(**position(text, j))
        sent = time.perf_counter()
        await client.text_document_completion_async(
            lsp.CompletionParams(lsp.TextDocumentIdentifier(URI), p))
        requests["completion (labels in TRJMP)"].append(time.perf_counter() - sent)
        p = lsp.Position(**position(text, j + 1))
        sent = time.perf_counter()
        await client.text_document_hover_async(lsp.HoverParams(lsp.TextDocumentIdentifier(URI), p))
        requests["hover on a label"].append(time.perf_counter() - sent)
    await client.shutdown_session()
    await client.stop()
    return {"size": len(text.encode()), "blocks": blocks, "ready": float("nan"),
            "open": float("nan"), "edits": edit_times, "requests": requests, "labels": None}


def cpu_seconds(pid: int) -> float:
    """The CPU time a process has used (user and system), in seconds (Linux: /proc/PID/stat):
    unlike the latencies, it does not grow when other processes load the machine."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def rss_mib(pid: int) -> float:
    """The resident memory of a process, in MiB (Linux: /proc/PID/status)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    raise RuntimeError("no VmRSS in /proc: --memory needs Linux")


async def bench_memory(edits: int, blocks: int = 124) -> dict:
    """RSS after the open of a script of about 20 KB (124 blocks), and after `edits` quick
    edits: a digit typed into a speed and deleted again, at blocks spread over the file,
    every edit's diagnostics awaited before the next edit is sent."""
    text = big_script(blocks)
    client = await RawClient.start()
    pid = client.process.pid
    await client.request("initialize", {"processId": os.getpid(), "rootUri": None,
                                        "capabilities": {}})
    client.notify("initialized", {})
    await client.diagnostics_after("textDocument/didOpen", {"textDocument": {
        "uri": URI, "languageId": "scriptc", "version": 1, "text": text}}, 1)
    version = 1
    samples = [(0, rss_mib(pid))]
    plan = edits_for(text, max(1, edits // 2))
    started = time.perf_counter()
    done = 0
    while done < edits:
        for start, end, new, _kind in plan:
            if done == edits:
                break
            rng = {"start": position(text, start), "end": position(text, end)}
            text = text[:start] + new + text[end:]
            version += 1
            done += 1
            await client.diagnostics_after("textDocument/didChange", {
                "textDocument": {"uri": URI, "version": version},
                "contentChanges": [{"range": rng, "text": new}]}, version)
            if done % 4 == 0:
                await client.request("textDocument/hover", {"textDocument": {"uri": URI},
                                                            "position": rng["start"]})
                await client.request("textDocument/inlayHint", {"textDocument": {"uri": URI},
                                                                "range": rng})
            if done % 500 == 0:
                samples.append((done, rss_mib(pid)))
    took = time.perf_counter() - started
    await client.stop()
    return {"size": len(text.encode()), "edits": edits, "samples": samples, "seconds": took}


def ms(seconds: float) -> str:
    return f"{seconds * 1000:6.1f} ms"


def summary(values: list[float]) -> str:
    values = sorted(values)
    p90 = values[min(len(values) - 1, int(len(values) * 0.9))]
    return (f"median {ms(statistics.median(values))}  p90 {ms(p90)}  "
            f"min {ms(values[0])}  max {ms(values[-1])}  (n={len(values)})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--blocks", type=int, default=560,
                        help="blocks of the script (560: ~90 KB)")
    parser.add_argument("--rounds", type=int, default=40, help="edits (x2) and requests per kind")
    parser.add_argument("--pygls", action="store_true", help="measure through pytest-lsp's client")
    parser.add_argument("--profile", metavar="FILE", help="run the server under cProfile, "
                        "writing its statistics to FILE (the figures are then not meaningful)")
    parser.add_argument("--memory", action="store_true",
                        help="measure the server's memory over a long session of quick edits")
    parser.add_argument("--edits", type=int, default=2000, help="edits of --memory")
    args = parser.parse_args()
    if args.memory:
        r = asyncio.run(bench_memory(args.edits))
        (_, first), (_, last) = r["samples"][0], r["samples"][-1]
        print(f"scriptc lsp over stdio; script of {r['size'] / 1000:.1f} KB, {r['edits']} quick "
              f"edits in {r['seconds']:.1f} s")
        print("  RSS: " + ", ".join(f"{mib:.1f} MiB after {n} edits" for n, mib in r["samples"]))
        print(f"  growth over the session: {last - first:+.1f} MiB "
              f"({(last - first) / r['edits'] * 1024:+.1f} KiB per edit)   target: flat")
        return
    if args.pygls:
        r = asyncio.run(bench_pygls(args.blocks, args.rounds))
    else:
        r = asyncio.run(bench(args.blocks, args.rounds, args.profile))
    client = "pytest-lsp (pygls) client" if args.pygls else "raw JSON-RPC client"
    print(f"scriptc lsp over stdio, {client}; script of {r['size'] / 1000:.1f} KB "
          f"({r['blocks']} blocks)")
    if not args.pygls:
        print(f"  start + initialize + open -> diagnostics: {ms(r['ready'])} "
              f"(didOpen -> diagnostics {ms(r['open'])})")
    every = r["edits"]["typing"] + r["edits"]["syntax"]
    print(f"  edit -> diagnostics (one block):  {summary(every)}   target: median <= 60 ms")
    print(f"    of which typing in a number:    {summary(r['edits']['typing'])}")
    print(f"    of which breaking/repairing:    {summary(r['edits']['syntax'])}")
    if r.get("edit_cpu") is not None:
        print(f"  server CPU time per edit:        {ms(r['edit_cpu'])} (user + system, "
              "the figure to compare on a loaded machine)")
    for name, values in r["requests"].items():
        print(f"  {name + ':':32} {summary(values)}   target: <= 20 ms")
    if r["labels"]:
        print(f"  (the label completion lists {r['labels']} labels)")


if __name__ == "__main__":
    main()
