"""Demo in Blender, headless: a rough Grease Pencil sketch simplified by the operator.

    python scripts/demo_blender.py [SAMPLE] [--out DIR]
    blender -b --python scripts/demo_blender.py -- [SAMPLE] [--out DIR]

Builds a scene with a Grease Pencil object drawn from a bundled sample, runs Simplify
Sketch as a user would (new layer, source hidden), saves DIR/<sample>.blend and writes
DIR/<sample>_blender_before_after.png.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
home = tempfile.mkdtemp(prefix="sketchsimp-demo-")
os.environ.setdefault("BLENDER_USER_RESOURCES", os.path.join(home, "user"))
os.environ.setdefault("XDG_CACHE_HOME", os.path.join(home, "cache"))
sys.path[:0] = [str(ROOT), str(ROOT / "tests"), str(ROOT / "scripts")]

import bpy  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from blender_scene import clear_scene, drawn_strokes, load_extension, make_object  # noqa: E402


def args_after_dashes() -> list[str]:
    if "--" in sys.argv:
        return sys.argv[sys.argv.index("--") + 1:]
    return sys.argv[1:] if bpy.app.binary_path == "" else []


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sample", nargs="?", default="house")
    ap.add_argument("--out", type=Path, default=ROOT / "out")
    args = ap.parse_args(args_after_dashes())
    args.out.mkdir(parents=True, exist_ok=True)
    extension = load_extension()
    extension.register()
    try:
        clear_scene()
        ob = make_object({1: args.sample}, name=args.sample.title())
        bpy.ops.sketchsimp.simplify()
        print(bpy.context.scene.sketchsimp.last_run)
        blend = args.out / f"{args.sample}.blend"
        bpy.ops.wm.save_as_mainfile(filepath=str(blend))
        before = [s[:, [0, 2]] for s in drawn_strokes(ob.data.layers["Lines"].frames[0].drawing)]
        after = [s[:, [0, 2]]
                 for s in drawn_strokes(ob.data.layers["Lines simplified"].frames[0].drawing)]
        fig, axes = plt.subplots(1, 2, figsize=(10, 5.2))
        for ax, strokes, label in ((axes[0], before, f"Grease Pencil: {len(before)} strokes"),
                                   (axes[1], after, f"Simplify Sketch: {len(after)} strokes")):
            for s in strokes:
                ax.plot(*s.T, lw=0.9)
            ax.set_title(label)
            ax.set_aspect("equal")
            ax.axis("off")
        png = args.out / f"{args.sample}_blender_before_after.png"
        fig.tight_layout()
        fig.savefig(png, dpi=90)
        print(f"wrote {blend} and {png}")
    finally:
        extension.unregister()
    return 0


if __name__ == "__main__":
    code = main()
    sys.stdout.flush()
    os._exit(code)
