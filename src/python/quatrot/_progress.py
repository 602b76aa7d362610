"""The progress bar of `quatrot.run(..., progress=True)`: tqdm when it is
installed, otherwise one line on stderr rewritten in place. `bar(total)`
returns a callable `(step, total)` with a `close()` method."""

import sys


class _Line:
    """`step/total steps` on stderr, rewritten in place."""

    def __init__(self, total):
        self.total = total

    def __call__(self, step, total):
        sys.stderr.write(f"\r{step}/{total} steps")
        sys.stderr.flush()

    def close(self):
        sys.stderr.write("\n")
        sys.stderr.flush()


class _Tqdm:
    """A tqdm bar moved to the step reached."""

    def __init__(self, tqdm, total):
        self.bar = tqdm(total=total, unit="step")

    def __call__(self, step, total):
        self.bar.update(step - self.bar.n)

    def close(self):
        self.bar.close()


def bar(total):
    """A progress reporter for a run of `total` steps."""
    try:
        from tqdm import tqdm
    except ImportError:
        return _Line(total)
    return _Tqdm(tqdm, total)
