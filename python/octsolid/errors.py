"""The exceptions octsolid raises: every one is an ``octsolid.Error``.

Each kind is also the built-in exception it is a case of, so ``except OSError``
catches a missing file and ``except ValueError`` a malformed one. The message is the
library's, naming the file and the place in it (``file: line 3: ...``, ``file: byte
12: ...``, ``scene.toml:4:9: ...``); ``filename`` is the file where there is one.
"""


class Error(Exception):
    """Any failure of octsolid: its message names the file and place when there is one."""

    filename = None


class FileError(Error, OSError):
    """A file could not be read or written (missing, unreadable, a folder in the way)."""


class FormatError(Error, ValueError):
    """A file's content or extension is not what its reader accepts, or it cannot be drawn."""


class ArgumentError(Error, ValueError):
    """An argument is refused: a negative radius, a depth out of range, a wrong array shape."""


class BudgetError(Error, MemoryError):
    """A job's estimated memory exceeds the memory budget; nothing was started."""
