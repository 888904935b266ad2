"""What every runner shares about its lifetime: it is a context manager that closes itself."""


class ClosesOnExit:
    """``with Runner(...) as runner:`` closes the runner at the end of the block; the class that
    mixes this in defines ``close()`` (idempotent)."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
