"""The installed ringlube version, as the packaging metadata records it.

The version is written once, in ``project(ringlube VERSION ...)`` of CMakeLists.txt;
scikit-build-core copies it into the package metadata, and CMake into the kernel
(``ringlube-solve --version``).
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("ringlube")
except PackageNotFoundError:  # imported from a source tree that was never installed
    __version__ = "0+unknown"


def kernel_id() -> str:
    """The identity of the installed kernel build: 12 hex digits hashed from the kernel's
    sources, compiler and flags (fortran/kernel_id.cmake). Results record it (HDF5 attribute
    ``kernel_id``); a study refuses to resume under another kernel.

    Returns
    -------
    str

    Example
    -------
    >>> len(kernel_id())
    12
    """
    from . import _kernel

    return _kernel.rl_kernel_id().decode().strip()


__all__ = ["__version__", "kernel_id"]
