"""``python -m derivations [OUTDIR]``: regenerate every committed generated file."""

import sys
from pathlib import Path

from .codegen import generate_all, KERNEL_DIR

out = Path(sys.argv[1]) if len(sys.argv) > 1 else KERNEL_DIR
for path in generate_all(out):
    print(f"wrote {path}")
