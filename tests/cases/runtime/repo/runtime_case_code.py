"""The Python code of the runtime cases' repository (scriptc.toml beside it): a function that
raises on an argument it cannot read, and a rule that posts, once, an update the map cannot
take (policy `X`) and one it can."""

from scriptc.runtime.rules import Rule


def closer(call, a, b):
    return float(a) < float(b)


class MarkSeen(Rule):
    def __init__(self, message, params=None):
        super().__init__(message, params)
        self.posted = False

    def on_true(self, ctx):
        if self.posted:
            return
        self.posted = True
        ctx.post_update("Human/kid1", "poses", "X", {"positionrho": 1.0})
        ctx.post_update("Human/kid1", "poses", "R", {"positionrho": 1.0, "positiontheta": 0.0})
