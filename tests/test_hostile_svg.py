"""Untrusted SVG files: each refused with a one-line error, in bounded time and memory.

The time limit on each test is a hang detector, not a speed target: every case here is
refused in well under a second.
"""

from __future__ import annotations

import subprocess
import sys

import pytest
from helpers import ROOT

from core.io.svg import MAX_SVG_ELEMENTS, MAX_SVG_NUMBERS, parse_svg
from core.sketch import SketchError

SVG = b'<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink">'


def laughs(levels: int = 10) -> bytes:
    entities = b'<!ENTITY l0 "lol">' + b"".join(
        b'<!ENTITY l%d "%s">' % (k, b"".join(b"&l%d;" % (k - 1) for _ in range(10)))
        for k in range(1, levels))
    return (b'<?xml version="1.0"?><!DOCTYPE svg [' + entities + b"]>" + SVG
            + b'<path d="M0 0 L1 1"/><text>&l%d;</text></svg>' % (levels - 1))


def use_bomb(levels: int = 40) -> bytes:
    """Each group uses the one before twice: 2 ** levels paths once expanded."""
    groups = b"".join(b'<g id="g%d"><use xlink:href="#g%d"/><use xlink:href="#g%d"/></g>'
                      % (k, k - 1, k - 1) for k in range(1, levels))
    return SVG + b'<g id="g0"><path d="M0 0 L1 1"/></g>' + groups + b"</svg>"


def huge_path(commands: int) -> bytes:
    d = b"M0 0" + b"".join(b" L%d %d" % (k % 997, k % 991) for k in range(commands))
    return SVG + b'<path d="' + d + b'"/></svg>'


HOSTILE = {
    "entity expansion": (laughs(), "unsafe XML"),
    "external entity": (b'<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY x SYSTEM '
                        b'"file:///etc/passwd">]>' + SVG + b'<path d="M0 0 L1 1"/>'
                        b"<text>&x;</text></svg>", "unsafe XML"),
    "external parameter entity": (b'<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY % x SYSTEM '
                                  b'"http://example.com/x.dtd"> %x;]>' + SVG + b"</svg>",
                                  "unsafe XML"),
    "use bomb": (use_bomb(), "elements once <use>"),
    "use loop": (SVG + b'<g id="a"><use xlink:href="#a"/><path d="M0 0 L1 1"/></g></svg>',
                 "refers to an element that contains it"),
    "huge path": (huge_path(MAX_SVG_NUMBERS // 2 + 1), "too much path data"),
    "not xml": (bytes(range(256)) * 4, "not well-formed"),
    "truncated": (SVG + b'<path d="M0 0 L1 1"', "not well-formed"),
    "empty document": (SVG + b"</svg>", "no drawable"),
    "only text": (SVG + b"<text>hello</text></svg>", "no drawable"),
    "empty path": (SVG + b'<path d=""/></svg>', "no drawable"),
    "zero-size shapes": (SVG + b'<rect width="0" height="0"/><circle r="0"/></svg>',
                         "no drawable"),
    "overflowing coordinates": (SVG + b'<path d="M0 0 L1e308 1e308 L-1e308 -1e308"/></svg>',
                                "too large"),
}


@pytest.mark.timeout(60)
@pytest.mark.parametrize("case", sorted(HOSTILE))
def test_hostile_svg_is_refused_with_one_line(case):
    data, message = HOSTILE[case]
    with pytest.raises(SketchError, match=message) as err:
        parse_svg(data, "hostile.svg")
    assert "\n" not in str(err.value) and str(err.value).startswith("hostile.svg")


@pytest.mark.parametrize("d, where", [
    ("M0 0 L foo bar", 7),
    ("M0 0 L 1", 8),  # a coordinate without its pair
    ("M0 0 C1 2 3 4", 13),  # a curve short of its end point
    ("Mx", 1),
    ("M nan 0 L 1 1", 2),
    ("M0,0 L1,1 #$%", 10),
    ("M0 0 A 1 1 0 2 2 5 5", 20),  # an arc flag must be 0 or 1
])
def test_malformed_path_data_names_where(d, where):
    data = SVG + b'<path id="stroke7" d="' + d.encode() + b'"/></svg>'
    with pytest.raises(SketchError, match=f"path stroke7: malformed path data at character "
                                          f"{where}"):
        parse_svg(data, "f.svg")


@pytest.mark.parametrize("d", ["M0 0 a1 1 0 015 5", "m0 0 1 1 2 2z", "M0,0L1,1 ", "M.5.5l1-1",
                               "M0 0 L1 1 Z M2 2 H3 V4 Q5 5 6 6 T7 7 S8 8 9 9"])
def test_compact_but_valid_path_data_is_read(d):
    data = SVG + b'<path d="' + d.encode() + b'"/></svg>'
    assert parse_svg(data).strokes


def test_legitimate_doctype_and_use_are_read():
    """A public DTD reference (Inkscape, Illustrator) is not an entity and loads nothing;
    <use> of a stroke drawn once is kept, twice."""
    data = (b'<?xml version="1.0"?><!DOCTYPE svg PUBLIC "-//W3C//DTD SVG 1.1//EN" '
            b'"http://www.w3.org/Graphics/SVG/1.1/DTD/svg11.dtd">' + SVG
            + b'<defs><path id="p" d="M0 0 L10 10"/></defs><use xlink:href="#p"/>'
            b'<use xlink:href="#p" transform="translate(5 0)"/></svg>')
    sketch = parse_svg(data)
    starts = sorted(tuple(s.points[0]) for s in sketch.strokes if len(s.points) == 2)
    assert (0.0, 0.0) in starts and (5.0, 0.0) in starts


def test_use_bomb_limit_leaves_room_for_real_drawings():
    """A drawing of many strokes, each drawn once, is far below the element limit."""
    paths = b"".join(b'<path d="M%d 0 L%d 10"/>' % (k, k) for k in range(5000))
    assert len(parse_svg(SVG + paths + b"</svg>").strokes) == 5000
    assert MAX_SVG_ELEMENTS > 5000


def test_oversized_file_is_refused_before_parsing(monkeypatch):
    import core.io.svg as svg
    monkeypatch.setattr(svg, "MAX_SVG_BYTES", 100)
    with pytest.raises(SketchError, match="larger than"):
        parse_svg(SVG + b'<path d="M0 0 L1 1"/>' * 10 + b"</svg>")


@pytest.mark.timeout(120)
def test_cli_refuses_hostile_files_with_one_line(tmp_path):
    for name, data in [("bomb.svg", use_bomb()), ("laughs.svg", laughs()),
                       ("bad.svg", SVG + b'<path d="M0 0 L foo"/></svg>')]:
        src = tmp_path / name
        src.write_bytes(data)
        out = tmp_path / f"out-{name}"
        proc = subprocess.run([sys.executable, "-m", "core", str(src), "-o", str(out)],
                              capture_output=True, text=True, cwd=ROOT, timeout=100)
        assert proc.returncode == 1, proc.stderr
        assert len(proc.stderr.strip().splitlines()) == 1, proc.stderr
        assert not out.exists()
