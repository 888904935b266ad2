"""What every runner shares about its lifetime: it is a context manager that closes itself, and
once closed it says so rather than answer (Box2D's runner handed out empty (0,) arrays after
``close()``, pybullet's the poses cached before it, pymunk's went on stepping)."""


class ClosesOnExit:
    """``with Runner(...) as runner:`` closes the runner at the end of the block; the class that
    mixes this in defines ``close()`` (idempotent), which sets ``closed``, and calls
    ``ensure_open()`` before every step and every read of the engine."""

    #: set by ``close()``
    closed = False

    def ensure_open(self):
        """ValueError if the runner was closed."""
        if self.closed:
            raise ValueError(
                f"{self.name}: this runner was closed (close(), or the end of its with block); "
                f"build a new one to step or read it"
            )

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
