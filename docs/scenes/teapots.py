#!/usr/bin/env python3
"""Writes a TOML scene of a grid of teapots that all name one model.

    python3 docs/scenes/teapots.py COLUMNS ROWS > teapots.toml

Every object is an instance of the embedded teapot: the GPU stores its 32
patches once, whatever the number of objects (docs/reyes.md, "Instancing").
"""

import math
import sys


def main() -> None:
    columns, rows = (int(a) for a in sys.argv[1:3])
    spacing = 4.0
    width, depth = (columns - 1) * spacing, (rows - 1) * spacing
    out = [
        "# A grid of teapots, every one an instance of the embedded teapot.",
        f"# Written by `python3 docs/scenes/teapots.py {columns} {rows}`.",
        "spp = 16",
        "",
        "[resolution]",
        "width = 800",
        "height = 450",
        "",
        "[camera]",
        f"eye = [{width / 2:.2f}, {-0.45 * depth - 12:.2f}, {0.7 * depth + 12:.2f}]",
        f"target = [{width / 2:.2f}, {depth / 2 - 3:.2f}, 0.0]",
        "up = [0.0, 0.0, 1.0]",
        "fov_y_degrees = 40.0",
        "",
        "[[lights]]",
        "direction = [-0.4, 0.6, -1.0]",
        "",
    ]
    surfaces = ['{ shader = "plastic", roughness = 0.1 }', '{ shader = "metal", roughness = 0.2 }', '{ shader = "matte" }']
    for row in range(rows):
        for column in range(columns):
            i = row * columns + column
            hue = (i * 0.618034) % 1.0
            r, g, b = (0.5 + 0.45 * math.cos(2 * math.pi * (hue + k / 3)) for k in range(3))
            out += [
                "[[objects]]",
                'model = "teapot"',
                f"color = [{r:.3f}, {g:.3f}, {b:.3f}]",
                f"surface = {surfaces[i % len(surfaces)]}",
                f"transform = {{ translate = [{column * spacing:.1f}, {row * spacing:.1f}, 0.0], "
                f"rotate_degrees = [0.0, 0.0, {(i * 47) % 360:.1f}] }}",
                "",
            ]
    print("\n".join(out))


if __name__ == "__main__":
    main()
