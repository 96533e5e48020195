"""``python -m impactsym.figures DIR``: write the README's figures and their source data into ``DIR``."""

from . import main

raise SystemExit(main())
