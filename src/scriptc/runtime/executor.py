"""The executor interface: one loaded script's block reading, and nothing else.

An executor is what differs between running a script from the IR (`interp.IRExecutor`, the
executable spec) and from verified bytecode (`vm.VMExecutor`, the one `scriptc run` uses; the
two must write the same trace). Everything else — the clock, the
map, the rules, the actuators, the robot, goal records, the LIFO queue, traces — is the
session's and is shared. An executor:

- knows its script's name, its alfa and omega messages (as `RuleMessage` values) and its
  goal ids (by goal index);
- `start()`: positions itself at the first block (goal 0, action 0, block 0);
- `seek(position)`: positions itself at any block (a rule's override), or raises SeekError;
- `read(ctx, sink)`: reads blocks from its position until
  - an instruction block: returns `Issue(position, instruction)`, the commands as plain
    values, and will continue after that block on the next `read`;
  - a terminus: returns `End(position, "terminus")`;
  - running past the last block: returns `End(position_of_last_block, "past_end")`.
  On the way it tells `sink` about every block it arrives at (`sink.visit(position)`: the
  session derives goal records from these), every jump (`sink.jump(...)`: position,
  condition text, the `Evaluation` and where it goes), and every sensor block
  (`sink.sensor(...)`). Jump conditions are evaluated against the map through the shared
  `EvalContext`: the executor calls `ctx.begin(READER, ctx.now)` before each condition (the
  session has set `ctx.now`) and reads the result with the context's primitives.
- `position`: the block it last read (None before the first read).

The executor never touches time, the actuators, rules or the trace; it cannot loop forever
on its own either: `read` gives up with `ReadLimit` after `max_blocks` blocks without an
instruction block (a jump cycle that lets no time pass, F002).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Generic, Protocol, TypeVar

from scriptc.runtime.commands import BlockAddress, BlockCommands, RuleMessage
from scriptc.runtime.evaluate import EvalContext, Evaluation


@dataclass(frozen=True, slots=True)
class Issue:
    """An instruction block to issue to the actuators."""

    position: BlockAddress
    instruction: BlockCommands
    label: str = ""


@dataclass(frozen=True, slots=True)
class End:
    """The script ends: `how` is "terminus" or "past_end" (ran past its last block)."""

    position: BlockAddress | None
    how: str


ReadResult = Issue | End


class SeekError(ValueError):
    """A seek to a block the script does not have."""


class ReadLimit(RuntimeError):
    """`read` passed `max_blocks` blocks without reaching an instruction block or the end."""


class ReadSink(Protocol):
    """What an executor reports while reading (the session implements it)."""

    def visit(self, position: BlockAddress) -> None: ...

    def jump(self, position: BlockAddress, condition: str, evaluation: Evaluation,
             target: BlockAddress | None) -> None: ...

    def sensor(self, position: BlockAddress, payload: tuple[str, ...]) -> None: ...


class Executor(Protocol):
    """One loaded script's block reader (see the module's docstring)."""

    name: str
    alfa: tuple[RuleMessage, ...]
    omega: tuple[RuleMessage, ...]
    goal_ids: tuple[str, ...]
    position: BlockAddress | None

    def start(self) -> None: ...

    def seek(self, position: BlockAddress) -> None: ...

    def read(self, ctx: EvalContext, sink: ReadSink, max_blocks: int = ...) -> ReadResult: ...


class ExecutableProgram(Protocol):
    """What `ExecutorBase` reads of a program (an `IRProgram`, a `VMProgram`): the script's
    name, messages and goal ids, and the index of each block by its position."""

    @property
    def name(self) -> str: ...

    @property
    def alfa(self) -> tuple[RuleMessage, ...]: ...

    @property
    def omega(self) -> tuple[RuleMessage, ...]: ...

    @property
    def goal_ids(self) -> tuple[str, ...]: ...

    @property
    def index(self) -> Mapping[tuple[int, int, int], int]: ...


P = TypeVar("P", bound=ExecutableProgram)


class ExecutorBase(Generic[P]):
    """What both executors share: the script's name, messages and goal ids from its program,
    the position, and finding a block by position (`program.index`) for `seek`."""

    def __init__(self, program: P) -> None:
        self.program = program
        self.name = program.name
        self.alfa = program.alfa
        self.omega = program.omega
        self.goal_ids = program.goal_ids
        self.position: BlockAddress | None = None

    def _index_of(self, position: BlockAddress) -> int:
        i = self.program.index.get(position)
        if i is None:
            raise SeekError(f"`{self.name}` has no block {position.path}")
        return i


class Loadable(Protocol):
    """A loadable script: its name, where it came from, and a fresh executor per load."""

    name: str
    path: str

    def executor(self) -> Executor: ...
