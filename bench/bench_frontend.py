"""Front end only: lark's raw parse of each item, scriptc's item parser (syntax/shapes.py) and
scan + parse + lower (prints figures)."""
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from generate import script_of_size

from scriptc.frontend.script import lower_script
from scriptc.source import SourceFile
from scriptc.syntax.parser import script_lark, script_parser
from scriptc.syntax.scan import scan

text = script_of_size(1.0)
mb = len(text) / 1e6
parser = script_lark()
shapes = script_parser()
items = [text[r.span.start:r.span.end] for r in scan(text).items]


def best(f, n=3):
    b = 1e9
    for _ in range(n):
        t = time.process_time()
        f()
        b = min(b, time.process_time() - t)
    return b


raw = best(lambda: [parser.parse(s, start="item") for s in items])
fast = best(lambda: [shapes.parse(s, start="item") for s in items])
low = best(lambda: lower_script(SourceFile("big.script", text)))
print(f"{mb:.2f} MB: lark parse of the items {mb/raw:.2f} MB/s; scriptc's item parser (shapes) "
      f"{mb/fast:.2f} MB/s; scan+parse+lower {mb/low:.2f} MB/s")
