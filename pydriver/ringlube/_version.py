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

__all__ = ["__version__"]
