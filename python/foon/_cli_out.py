"""``foon plan --out DIR``: the file name of each goal, and a writer that writes every file
or none.

Names: a goal's stem is its label with spaces, path separators and the characters that
common file systems reject as ``_`` (see :func:`file_stem`). Stems are compared as a
case-insensitive file system would (Unicode NFC, then case-folded), so ``Ice`` and ``ice``
count as one name everywhere and the output is the same on every file system. In goal order,
the first goal with a stem gets it; a later goal with a stem already given (or one that
another goal has as its own stem) gets ``STEM_2``, ``STEM_3``, ...: the smallest number
whose name is still free. The names depend on the goal list only, never on the results: a
goal that fails keeps its name but gets no file.
"""

from __future__ import annotations

import os
import sys

TYPE_CHECKING = False
if TYPE_CHECKING:
    from collections.abc import Sequence

#: Characters that may not stand in a file name made from a label (path separators, and
#: what common file systems reject); each becomes ``_``, as spaces do.
_UNSAFE_IN_NAME = str.maketrans({c: "_" for c in ' /\\:*?"<>|'})


class OutError(Exception):
    """A destination that cannot be written (exit code 1); the message names it."""


def file_stem(label: str) -> str:
    """The file name (without extension) for a goal: its label with spaces as ``_`` (the
    course's naming), and path separators and other unsafe characters as ``_`` too, so that a
    label can never name a file outside the output folder."""
    stem = "".join("_" if ord(c) < 32 else c for c in label.translate(_UNSAFE_IN_NAME))
    return "_" + stem if stem in ("", ".", "..") else stem


def name_key(stem: str) -> str:
    """What two names must differ in to be two files on every file system."""
    import unicodedata

    return unicodedata.normalize("NFC", stem).casefold()


def file_names(labels: Sequence[str], ext: str) -> list[str]:
    """One distinct file name per label, by the rule in the module docstring."""
    stems = [file_stem(label) for label in labels]
    keys = [name_key(s) for s in stems]
    taken: set[str] = set()
    first = []
    for k in keys:
        first.append(k not in taken)
        taken.add(k)
    names = []
    next_suffix: dict[str, int] = {}  # per stem: no smaller suffix can still be free
    for stem, k, is_first in zip(stems, keys, first, strict=True):
        if is_first:
            names.append(stem + ext)
            continue
        n = next_suffix.get(k, 2)
        while name_key(f"{stem}_{n}") in taken:
            n += 1
        next_suffix[k] = n + 1
        taken.add(name_key(f"{stem}_{n}"))
        names.append(f"{stem}_{n}{ext}")
    return names


def is_stream(path: str) -> bool:
    """Whether ``path`` is (or links to) something other than a file or folder: a device
    such as ``/dev/stdout`` or ``/dev/null``, a FIFO, a socket. Such a destination is
    written into; renaming a file over it would remove it."""
    import stat

    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):
        return False
    return not (stat.S_ISREG(mode) or stat.S_ISDIR(mode))


def _same_file(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def _name_max(folder: str) -> int:
    """The longest file name (in bytes) the folder's file system takes (255 if unknown)."""
    while True:
        try:
            return int(os.pathconf(folder, "PC_NAME_MAX"))
        except (OSError, ValueError, AttributeError):
            parent = os.path.dirname(folder)
            if not folder or parent == folder:
                return 255
            folder = parent


class OutDir:
    """Writes one file per goal into a folder: every destination is checked before anything
    is written, each file goes to a temporary file first (created with the usual permissions,
    that is 0666 less the umask), and :meth:`commit` renames them all into place; on any
    failure the files already replaced are put back, the new files, the temporary files and
    the folders created are removed, and the error names the real destination."""

    def __init__(self, folder: str, names: Sequence[str], inputs: Sequence[str | None]) -> None:
        self.folder = folder
        self.dests = [os.path.join(folder, n) for n in names]
        self._temps: dict[int, str] = {}
        self._created: list[str] = []
        self._check(names, [i for i in inputs if i is not None])

    def _check(self, names: Sequence[str], inputs: Sequence[str]) -> None:
        # The folder, or its nearest existing ancestor, must be a writable directory.
        probe = self.folder
        while not os.path.lexists(probe):
            parent = os.path.dirname(probe) or "."
            if parent == probe:
                break
            probe = parent
        if not os.path.isdir(probe):
            raise OutError(f"{probe}: not a directory")
        if not os.access(probe, os.W_OK | os.X_OK):
            raise OutError(f"{probe}: permission denied")
        limit = _name_max(probe)
        for name, dest in zip(names, self.dests, strict=True):
            size = len(os.fsencode(name))
            if size > limit:
                raise OutError(
                    f"{dest}: file name too long ({size} bytes; this file system "
                    f"takes at most {limit})"
                )
            if os.path.isdir(dest) and not os.path.islink(dest):
                raise OutError(f"{dest}: is a directory")
            if is_stream(dest):
                # The rename of commit() would replace the device or pipe with a file.
                raise OutError(f"{dest}: not a regular file (a device, pipe or socket)")
            for i in inputs:
                if _same_file(dest, i):
                    raise OutError(f"{dest}: refusing to overwrite an input file")

    def _make_folder(self) -> None:
        missing = []
        # "trees/" and "trees" are one folder: trailing separators are not a folder of their own.
        d = self.folder.rstrip(os.sep + (os.altsep or "")) or self.folder
        while d and not os.path.lexists(d):
            missing.append(d)
            parent = os.path.dirname(d)
            if parent == d:
                break
            d = parent
        for d in reversed(missing):
            try:
                os.mkdir(d)
            except OSError as e:
                raise OutError(f"{d}: cannot create the folder: {e.strerror or e}") from None
            self._created.append(d)

    def write(self, i: int, data: str | bytes) -> None:
        """Writes the output of goal ``i`` (text as UTF-8, or bytes) to a temporary file
        beside its destination."""
        if not self._created and not self._temps:
            self._make_folder()
        dest = self.dests[i]
        flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0)
        for _ in range(100):
            tmp = self._temp_name()
            try:
                fd = os.open(tmp, flags, 0o666)
                break
            except FileExistsError:
                continue
            except OSError as e:
                raise OutError(f"{dest}: cannot write: {e.strerror or e}") from None
        else:
            raise OutError(f"{dest}: cannot create a temporary file")
        self._temps[i] = tmp
        try:
            with os.fdopen(fd, "wb") as fh:
                fh.write(data.encode("utf-8") if isinstance(data, str) else data)
        except OSError as e:
            raise OutError(f"{dest}: cannot write: {e.strerror or e}") from None

    def _temp_name(self) -> str:
        return os.path.join(self.folder, f".foon-{os.getpid()}-{os.urandom(6).hex()}.tmp")

    def _backup(self, dest: str) -> str | None:
        """Keeps the file at ``dest`` (if any) under a temporary name, so that it can be put
        back: a second link when the file system has them, else a rename."""
        if not os.path.lexists(dest):
            return None
        backup = self._temp_name()
        try:
            os.link(dest, backup, follow_symlinks=False)
        except OSError:
            try:
                os.rename(dest, backup)
            except OSError as e:
                raise OutError(f"{dest}: cannot replace: {e.strerror or e}") from None
        return backup

    def commit(self) -> None:
        """Renames every temporary file into place: all of them, or none (on failure the
        files replaced so far are put back and the new ones removed)."""
        done: list[tuple[str, str | None]] = []  # (destination, what it held before)
        try:
            for i in sorted(self._temps):
                dest = self.dests[i]
                try:
                    done.append((dest, self._backup(dest)))
                    os.replace(self._temps[i], dest)
                except OSError as e:
                    raise OutError(f"{dest}: cannot write: {e.strerror or e}") from None
                del self._temps[i]
        except OutError:
            for dest, backup in reversed(done):
                if backup is None:
                    _unlink(dest, missing_ok=True)
                else:
                    try:
                        os.replace(backup, dest)
                    except OSError as e:
                        print(f"foon: warning: {dest}: could not be put back (it is in "
                              f"{backup}): {e.strerror or e}", file=sys.stderr)  # fmt: skip
            self.abort()
            raise
        for _, backup in done:
            if backup is not None:
                _unlink(backup)
        self._created.clear()

    def abort(self) -> None:
        """Removes the temporary files and the folders this writer created."""
        for tmp in self._temps.values():
            _unlink(tmp)
        self._temps.clear()
        for d in reversed(self._created):
            try:
                os.rmdir(d)
            except OSError:
                pass
        self._created.clear()


def _unlink(path: str, missing_ok: bool = False) -> None:
    try:
        os.unlink(path)
    except FileNotFoundError:
        if not missing_ok:
            print(f"foon: warning: {path}: cannot remove: it is gone", file=sys.stderr)
    except OSError as e:
        print(f"foon: warning: {path}: cannot remove: {e.strerror or e}", file=sys.stderr)
