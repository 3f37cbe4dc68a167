"""Writes sky.png, the latitude-longitude environment of the material
gallery (docs/scenes/materials.toml): a blue sky with a sun above the
horizon and a grey checkered floor below it, z up (docs/reyes.md).

    python3 docs/scenes/sky.py docs/scenes/sky.png
"""
import sys

import numpy as np
from PIL import Image

WIDTH, HEIGHT = 512, 256

t = (np.arange(HEIGHT) + 0.5) / HEIGHT
s = (np.arange(WIDTH) + 0.5) / WIDTH
latitude = (0.5 - t)[:, None] * np.pi  # +pi/2 at the top row
longitude = s[None, :] * 2 * np.pi
up = np.sin(latitude)  # the direction's z
x = np.cos(latitude) * np.cos(longitude)
y = np.cos(latitude) * np.sin(longitude)

zenith = np.array([0.12, 0.32, 0.75])
horizon = np.array([0.85, 0.9, 1.0])
height = np.clip(up, 0.0, 1.0)[..., None] ** 0.5
sky = horizon + (zenith - horizon) * height * np.ones((1, WIDTH, 1))

# The sun, 35 degrees up towards -x +y (behind the camera's left).
sun = np.array([-0.6, 0.45, np.sin(np.radians(35.0))])
sun /= np.linalg.norm(sun)
facing = x * sun[0] + y * sun[1] + up * sun[2]
sky += np.clip((facing - 0.995) / 0.005, 0.0, 1.0)[..., None] * np.array([1.0, 0.95, 0.8])

# The floor: squares of 20 degrees of longitude by the distance of the
# floor point (z = -1) from the nadir.
below = np.clip(-up, 1e-3, 1.0)
reach = np.cos(latitude) / below  # horizontal distance on the plane z = -1
checker = (np.floor(longitude / np.radians(20.0)) + np.floor(reach / 0.6)) % 2
floor = np.where(checker[..., None] > 0, 0.55, 0.3) * np.ones(3)
image = np.where((up > 0)[..., None], sky, floor)

encoded = np.clip(image, 0.0, 1.0) ** (1 / 2.2)
Image.fromarray((encoded * 255 + 0.5).astype(np.uint8)).save(sys.argv[1])
