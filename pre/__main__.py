"""``python -m pre``: the same as the ``pre`` command."""
import sys

from .main import main

sys.exit(main())
