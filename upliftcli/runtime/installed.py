"""What is installed and where it runs, as the provenance records it (provenance.base) and
`uplift --version` prints it: the version of a distribution, read from its package metadata,
and the platform. Neither imports importlib.metadata (20-25 ms for a command) nor starts a
subprocess where it can be avoided (platform.platform() forks `uname -p` on Linux: 4-9 ms).
"""

from __future__ import annotations

import os
import platform
import re
import sys

#: the command and the tool's name (provenance records it)
TOOL = "uplift"
#: the distribution whose metadata holds the version (PyPI's `uplift` is an unrelated package)
DISTRIBUTION = "upliftcli"


def package_version(name: str) -> str:
    """The installed version of a distribution: the Version field of the first
    <name>-<version>.dist-info on sys.path, which importlib.metadata.version reads too
    (importing that module costs a command 20-25 ms); importlib.metadata itself for any other
    kind of installation (an .egg-info, a zip). "not installed" if it is not, "unknown" if its
    metadata has no version."""
    found = _dist_info_version(_distribution_key(name))
    if found:
        return found
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(name) or "unknown"
    except PackageNotFoundError:
        return "not installed"
    except (KeyError, OSError, ValueError):  # metadata without a version (an importlib_metadata backport raises)
        return "unknown"


def _dist_info_version(wanted: str) -> str | None:
    """The Version of the first <wanted>-<version>.dist-info on sys.path that gives one (None: none does)."""
    for folder in (entry or "." for entry in sys.path):
        for item in (item for item in _listing(folder) if _is_dist_info_of(item, wanted)):
            found = _metadata_version(os.path.join(folder, item, "METADATA"))
            if found:
                return found
    return None


def _is_dist_info_of(item: str, wanted: str) -> bool:
    """Whether a folder name is a <wanted>-<version>.dist-info (_distribution_key compares the names)."""
    return item.endswith(".dist-info") and _distribution_key(item.split("-", 1)[0]) == wanted


def _listing(folder: str) -> list[str]:
    """The names in a folder; none for anything else on sys.path (a zip, an import hook)."""
    try:
        return os.listdir(folder)
    except OSError:  # not a directory: a zip, an import hook
        return []


def _distribution_key(name: str) -> str:
    """A distribution name compared as its dist-info directory spells it (case and runs of
    '-', '_', '.' folded)."""
    return re.sub(r"[-_.]+", "_", name).lower()


def _metadata_version(path: str) -> str | None:
    """The Version header of a METADATA file (None if unreadable or absent)."""
    try:
        with open(path, encoding="utf-8") as metadata:
            for line in metadata:
                if not line.strip():  # the headers end at the first blank line
                    return None
                if line.startswith("Version:"):
                    return line[len("Version:"):].strip() or None
    except OSError:
        return None
    return None


def platform_name() -> str:
    """platform.platform(): system, release, machine and C library, Linux-6.1.0-x86_64-with-glibc2.36.
    On Linux from os.uname(): platform.platform() also asks a `uname -p` subprocess (4-9 ms) for
    the processor, which it leaves out when that is unknown or the machine again."""
    if not sys.platform.startswith("linux"):
        return platform.platform()
    system = os.uname()
    libc = "".join(platform.libc_ver())
    parts = (system.sysname, system.release, system.machine, "with" if libc else "", libc)
    text = "-".join(part.strip() for part in parts if part).replace(" ", "_")
    text = re.sub(r'[/\\:;"()]', "-", text)  # as platform.platform() cleans them
    return re.sub(r"-{2,}", "-", text).strip("-")


def tool_version() -> str:
    """The version of uplift (the metadata of the distribution upliftcli), "0+unknown" when it is not
    installed."""
    found = package_version(DISTRIBUTION)
    return "0+unknown" if found == "not installed" else found
