"""`python -m quatrot ARGS`: the `quatrot` command line (`run`, `scenes`,
`check`, `sweep`), run by the same Rust entry point as the `quatrot`
binary through the native module."""

import os
import signal
import sys

from quatrot import _native


def main() -> int:
    # Ctrl-C acts as it does on the binary (Python's handler would only set
    # a flag the Rust command never looks at).
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    # A closed pipe (`python -m quatrot scenes | head`) ends the command quietly.
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    # `quatrot sweep` starts Python: this one, which has quatrot.
    os.environ.setdefault("QUATROT_PYTHON", sys.executable)
    return _native.cli_main(["quatrot", *sys.argv[1:]])


if __name__ == "__main__":
    sys.exit(main())
