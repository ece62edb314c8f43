"""Laws of the bytecode for every input (hypothesis):

- every generated script that compiles gives a program that verifies, and decoding then
  re-encoding its file gives the same bytes;
- a corrupted file (bytes flipped, set, inserted, deleted, the file cut) is refused with a
  MalformedError or InvalidError, or else it is a program that verifies (and lists); never
  another exception. Corruptions come raw (the checksum catches them) and resealed (the header's
  length and CRC fixed up, so that the decoder's and the verifier's own checks are reached).
"""

from __future__ import annotations

import struct
import sys
import zlib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import scripts

from scriptc.analysis.analyze import analyze_script
from scriptc.bytecode import BytecodeError, decode, disassemble, encode, load
from scriptc.emit.codegen import codegen
from scriptc.source import SourceFile

ROOT = Path(__file__).parent.parent
sys.path.insert(0, str(ROOT / "bench"))

from generate import big_script  # noqa: E402 - after the path to bench/ is set

FAST = settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
MANY = settings(max_examples=500, deadline=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def _compile(text: str, name: str = "t.script") -> bytes:
    source = SourceFile(name, text)
    analysis = analyze_script(source)
    assert analysis.ok, analysis.diagnostics
    return encode(codegen(analysis.script, source))


@pytest.mark.slow
@FAST
@given(scripts())
def test_generated_scripts_compile_verify_and_round_trip(text: str) -> None:
    source = SourceFile("gen.script", text)
    analysis = analyze_script(source)
    if not analysis.ok:  # a generated jump cycle, say: the checks refuse it, no bytecode
        return
    program = codegen(analysis.script, source)
    data = encode(program)
    loaded = load(data).program
    assert loaded == program
    assert encode(loaded) == data
    assert disassemble(loaded)


# The programs to corrupt: the thesis example, the case with every instruction, a generated
# one with searches in many blocks.
SAMPLES = [
    _compile((ROOT / "examples" / "test_act.script").read_text(encoding="utf-8")),
    _compile((ROOT / "tests" / "cases" / "bytecode" / "conditions.script")
             .read_text(encoding="utf-8")),
    _compile(big_script(40), "big.script"),
]


def _reseal(data: bytes) -> bytes:
    if len(data) < 16:
        return data
    body = data[16:]
    return data[:8] + struct.pack("<II", len(body), zlib.crc32(body)) + body


def _code_section(data: bytes) -> tuple[int, int]:
    _sid, offset, length = struct.unpack_from("<HII", data, 18 + 10 * 3)
    return offset, offset + length


@st.composite
def corruptions(draw) -> bytes:
    data = bytearray(draw(st.sampled_from(SAMPLES)))
    # Where to corrupt: anywhere, or inside the code section (where the verifier works).
    low, high = 0, len(data)
    if draw(st.booleans()):
        low, high = _code_section(bytes(data))
    for _ in range(draw(st.integers(1, 3))):
        at = draw(st.integers(low, max(low, min(high, len(data)) - 1)))
        how = draw(st.sampled_from(["flip", "set", "insert", "delete", "cut", "u32"]))
        if how == "flip" and at < len(data):
            data[at] ^= 1 << draw(st.integers(0, 7))
        elif how == "set" and at < len(data):
            data[at] = draw(st.integers(0, 255))
        elif how == "insert":
            data[at:at] = draw(st.binary(min_size=1, max_size=8))
        elif how == "delete":
            del data[at:at + draw(st.integers(1, 8))]
        elif how == "cut":
            del data[at:]
        elif how == "u32" and at + 4 <= len(data):
            value = draw(st.sampled_from([0, 1, 2, 0xFF, 0xFFFF, 0x7FFF_FFFF, 0xFFFF_FFFF]))
            data[at:at + 4] = struct.pack("<I", value)
    data = bytes(data)
    return _reseal(data) if draw(st.booleans()) else data


@pytest.mark.slow
@MANY
@given(corruptions())
def test_corrupted_files_are_refused_cleanly(data: bytes) -> None:
    try:
        program = load(data).program
    except BytecodeError as exc:
        assert exc.message and str(exc).startswith(("malformed bytecode: ",
                                                    "invalid bytecode: "))
        return
    # Still a program: it verifies, lists, and survives its own round trip.
    assert disassemble(program)
    assert decode(encode(program)) == program


@pytest.mark.parametrize("sample", range(len(SAMPLES)))
def test_every_single_byte_flip_is_caught(sample: int) -> None:
    """CRC-32 catches every one-bit error in the body; the header checks catch the rest."""
    data = SAMPLES[sample]
    for at in range(0, len(data), max(1, len(data) // 400)):
        corrupted = bytearray(data)
        corrupted[at] ^= 0x04
        with pytest.raises(BytecodeError):
            load(bytes(corrupted))
