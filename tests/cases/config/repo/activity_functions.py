"""The implementations that tests/cases/config/repo/scriptc.toml declares (imported only when
asked: tests/test_config.py checks that linting never imports this module)."""


def waving(entity) -> bool:
    return bool(entity.get("waving"))


def mood(who) -> str:
    return "calm"
