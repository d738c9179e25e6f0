"""Build the installable extension: dist/sketchsimp-<version>-<platform>.zip.

    python scripts/build_extension.py [--check-only]

Downloads the wheels the manifest lists (shapely for each platform's Blender Python 3.11,
and the pure-Python svgelements and defusedxml) into wheels/, stages only what the
extension is made of, validates it with Blender's own extension tool (shipped inside the
bpy wheel), then builds with it, one zip per platform.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: what the extension is made of; everything else in the repository stays out
CONTENTS = ["blender_manifest.toml", "__init__.py", "core", "sketchsimp_addon", "wheels"]
#: left out of those: the command line and the cluster engine are applications of core, not
#: part of the add-on (Dask is never shipped in the extension)
LEFT_OUT = ["__pycache__", "*.pyc", "cli", "__main__.py", "cluster.py", "remote.py"]


def blender_ext_cli() -> Path:
    """Blender's extension command line, from the installed bpy wheel."""
    import importlib.util

    spec = importlib.util.find_spec("bpy")
    if spec is None or not spec.submodule_search_locations:
        sys.exit("build_extension: the bpy wheel is not installed (run make test or make venv)")
    found = sorted(Path(spec.submodule_search_locations[0]).glob(
        "*/scripts/addons_core/bl_pkg/cli/blender_ext.py"))
    if not found:
        sys.exit("build_extension: blender_ext.py not found inside the bpy wheel")
    return found[-1]


def download_wheels(manifest: dict) -> None:
    wheels = ROOT / "wheels"
    wheels.mkdir(exist_ok=True)
    for entry in manifest.get("wheels", []):
        path = ROOT / entry
        if path.exists():
            continue
        name, version, *rest = path.name[:-4].split("-")
        platform = rest[-1]
        cmd = [sys.executable, "-m", "pip", "download", "--quiet", "--no-deps",
               "--only-binary=:all:", "-d", str(wheels), f"{name}=={version}"]
        if platform != "any":
            cmd += ["--python-version", "3.11", "--implementation", "cp", "--platform",
                    platform.split(".")[-1]]
        subprocess.run(cmd, check=True)
        if not path.exists():
            sys.exit(f"build_extension: pip did not fetch {path.name}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check-only", action="store_true", help="validate, do not build")
    ap.add_argument("--output-dir", type=Path, default=ROOT / "dist")
    args = ap.parse_args()
    manifest = tomllib.loads((ROOT / "blender_manifest.toml").read_text())
    cli = blender_ext_cli()
    download_wheels(manifest)
    with tempfile.TemporaryDirectory() as tmp:
        stage = Path(tmp) / manifest["id"]
        stage.mkdir()
        for name in CONTENTS:
            src = ROOT / name
            if src.is_dir():
                shutil.copytree(src, stage / name, ignore=shutil.ignore_patterns(*LEFT_OUT))
            else:
                shutil.copy2(src, stage / name)
        subprocess.run([sys.executable, str(cli), "validate", str(stage)], check=True)
        if args.check_only:
            return 0
        args.output_dir.mkdir(parents=True, exist_ok=True)
        subprocess.run([sys.executable, str(cli), "build", "--source-dir", str(stage),
                        "--output-dir", str(args.output_dir), "--split-platforms"], check=True)
    for zip_path in sorted(args.output_dir.glob(f"{manifest['id']}-{manifest['version']}-*.zip")):
        print(f"built {zip_path} ({zip_path.stat().st_size // 1024} KiB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
