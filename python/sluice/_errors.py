"""The exceptions of the sluice package: one base class, subclasses by family.

Every exception carries ``code``, the name of the C++ ``sluice::ErrorCode`` (``"Truncated"``,
``"MeshImport"``, ...), and the message the command lines print (``str(e)``).
"""

from __future__ import annotations


class Error(Exception):
    """Base class of every error Sluice reports. ``code`` is the ErrorCode name."""

    def __init__(self, message: str, code: str = "Unknown") -> None:
        super().__init__(message)
        self.code = code

    def __reduce__(self):  # picklable, so errors cross process and Dask workers
        return (type(self), (str(self), self.code))


class FileError(Error):
    """A file cannot be opened, read, written or renamed (code ``Io``)."""


class MeshError(Error):
    """A mesh cannot be used: assimp could not read it, no triangles, NaN coordinates, too big."""


class AssetError(Error):
    """A collider asset is damaged or hostile: truncated, bad magic, version, sizes, checksum."""


class SceneError(Error):
    """A scene file is wrong; the message names the file and the JSON path."""


class GpuError(Error):
    """No OpenGL 4.5 context, a shader that does not compile or link, or GPU memory exhausted."""


class BakeError(Error):
    """A bake that cannot be done: the grid is too large, the CGAL reference failed, ..."""


class InvalidArgument(Error, ValueError):
    """An argument out of range (code ``InvalidArgument``)."""


_GPU_CODES = {"NoGlContext", "ShaderCompile", "ShaderLink", "GpuOutOfMemory"}
_ASSET_CODES = {"Truncated", "BadMagic", "UnsupportedVersion", "BadHeader", "SizeMismatch",
                "OffsetOutOfRange", "ChecksumMismatch", "BadMetadata"}


def error_class(code: str, family: str) -> type[Error]:
    """The class for an ErrorCode name raised while handling `family` (docs/python.md)."""
    if code in _GPU_CODES:
        return GpuError
    if code == "Io":
        return FileError
    if code == "InvalidArgument" and family != "scene":
        return InvalidArgument
    if family == "scene":
        return SceneError
    if family == "mesh" or code in ("MeshImport", "EmptyMesh"):
        return MeshError
    if family == "asset" or code in _ASSET_CODES:
        return AssetError
    if family == "argument":
        return InvalidArgument
    return BakeError
