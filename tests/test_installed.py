"""What is installed (upliftcli/runtime/installed.py): distribution versions as importlib.metadata reads
them, the platform as platform.platform() names it, the tool's version when it is not installed."""

from __future__ import annotations

import platform
import sys

import pytest

from upliftcli.provenance import record as provenance
from upliftcli.runtime import installed


def test_package_version_reads_what_importlib_metadata_reads(tmp_path, monkeypatch):
    from importlib.metadata import version

    for name in ("numpy", "scipy", "matplotlib", "typer"):
        assert installed.package_version(name) == version(name)
    assert installed.package_version("no-such-distribution-xyz") == "not installed"
    # a dist-info found by its folded name; one without a Version header: importlib.metadata, "unknown"
    (tmp_path / "My.Tool-2.5.1.dist-info").mkdir()
    (tmp_path / "My.Tool-2.5.1.dist-info" / "METADATA").write_text(
        "Metadata-Version: 2.1\nName: My.Tool\nVersion: 2.5.1\n\nVersion: 9 (the description)\n")
    (tmp_path / "broken-1.0.dist-info").mkdir()
    (tmp_path / "broken-1.0.dist-info" / "METADATA").write_text("Name: broken\n\nVersion: 1.0\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    assert installed.package_version("my_tool") == installed.package_version("MY-TOOL") == "2.5.1"
    assert installed.package_version("broken") == "unknown"


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the Linux branch")
def test_platform_name_is_platform_platform():
    machine = platform.uname().machine
    if platform.uname().processor not in ("", "unknown", machine):
        pytest.skip("platform.platform() names a processor other than the machine here")
    assert installed.platform_name() == platform.platform()
    assert provenance.base()["platform"] == platform.platform()


def test_tool_version_is_the_distribution_upliftclis(tmp_path, monkeypatch):
    """The version is read from the metadata of upliftcli (the distribution), never from PyPI's
    unrelated `uplift` installed beside it; the command and the tool's name stay `uplift`."""
    for name, number in (("uplift", "0.0.6"), ("upliftcli", "7.1.2")):
        (tmp_path / f"{name}-{number}.dist-info").mkdir()
        (tmp_path / f"{name}-{number}.dist-info" / "METADATA").write_text(
            f"Metadata-Version: 2.1\nName: {name}\nVersion: {number}\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    assert (installed.DISTRIBUTION, installed.TOOL) == ("upliftcli", "uplift")
    assert installed.tool_version() == "7.1.2"
    assert provenance.base()["version"] == "7.1.2" and provenance.base()["tool"] == "uplift"


def test_tool_version_when_not_installed(monkeypatch):
    monkeypatch.setattr(installed, "package_version", lambda name: "not installed")
    assert installed.tool_version() == "0+unknown"
