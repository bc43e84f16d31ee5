"""The exceptions octsolid raises: every one is an ``octsolid.Error``.

Each kind is also the built-in exception it is a case of, so ``except OSError``
catches a missing file and ``except ValueError`` a malformed one. The message is the
library's, naming the file and the place in it (``file: line 3: ...``, ``file: byte
12: ...``, ``scene.toml:4:9: ...``); ``filename`` is the file where there is one, and
``errno`` and ``strerror`` the operating system's error where it gave one.
"""


class Error(Exception):
    """Any failure of octsolid: its message names the file and place when there is one."""

    filename = None


class FileError(Error, OSError):
    """A file could not be read or written (missing, unreadable, a folder in the way).

    ``errno`` is the operating system's error number when it gave one
    (``e.errno == errno.ENOENT`` for a missing file), as for Python's own ``open``.
    """

    def __str__(self):
        # OSError's own shows "[Errno 2] strerror: 'filename'" once errno is set; the
        # library's message names the file and says why already.
        return str(self.args[0]) if self.args else super().__str__()


class FormatError(Error, ValueError):
    """A file's content or extension is not what its reader accepts, or it cannot be drawn."""


class ArgumentError(Error, ValueError):
    """An argument is refused: a negative radius, a depth out of range, a wrong array shape."""


class BudgetError(Error, MemoryError):
    """A job's estimated memory exceeds the memory budget; nothing was started."""


class InputWarning(UserWarning):
    """What a reader read past without refusing the file (an unknown PLY header line, a
    missing ``.mtl``), naming the file and place, as the CLI's ``warning:`` lines."""


class ClippedWarning(UserWarning):
    """An offset, shell or round reached a face of the solid's domain: what lay past it
    is cut off (give the solid a larger domain first: ``solid.transform(domain=...)``),
    or nothing was left of it."""
