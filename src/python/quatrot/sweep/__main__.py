"""`python -m quatrot.sweep`: see `quatrot.sweep.cli`."""

import sys

from quatrot.sweep.cli import main

sys.exit(main())
