"""The one diagnostic model (`model.py`), the registry of codes (`codes.py`) and the renderers
(`render.py`). Every stage reports through this package; none of it imports a later stage."""

from scriptc.diagnostics.model import Diagnostic, Fix, Label, Severity, TextEdit, diagnostic

__all__ = ["Diagnostic", "Fix", "Label", "Severity", "TextEdit", "diagnostic"]
