"""The one diagnostic model (`model.py`), the registry of codes (`codes.py`, above the model:
it builds diagnostics with their code's severity) and the renderers (`render.py`). Every stage
reports through this package; none of it imports a later stage."""

from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic, Fix, Label, Severity, TextEdit

__all__ = ["Diagnostic", "Fix", "Label", "Severity", "TextEdit", "diagnostic"]
