#!/usr/bin/env python3
"""Writes the rigid helices of Rodenborn, Chen, Swinney, Liu & Zhang,
"Propulsion of microorganisms by a helical flagellum", PNAS 110, E338-E347
(2013), as MJCF models of capsules: helix radius R = 6.3 mm, axial length
130 mm, filament radius 0.397 mm, pitch lambda = (2.226, 3.677, 6.509,
9.811, 15.241) R. The helix's axis is the world x axis, centred on the
origin; 64 capsules per turn along its centreline. The fluid is RFT
(Gray & Hancock, lambda the pitch) in the experiment's silicone oil
(viscosity 1 Pa s; the coefficients scale with it and the published
numbers are divided by it). Run from anywhere: writes beside itself.
"""
import math
import pathlib

HELIX_RADIUS_M = 6.3e-3
AXIAL_LENGTH_M = 130e-3
FILAMENT_RADIUS_M = 0.397e-3
PITCH_OVER_RADIUS = (2.226, 3.677, 6.509, 9.811, 15.241)
CAPSULES_PER_TURN = 64


def helix_mjcf(pitch_over_radius):
    pitch_m = pitch_over_radius * HELIX_RADIUS_M
    turns = AXIAL_LENGTH_M / pitch_m
    capsules = math.ceil(turns * CAPSULES_PER_TURN)
    points = []
    for k in range(capsules + 1):
        theta = 2 * math.pi * turns * k / capsules
        points.append((pitch_m * theta / (2 * math.pi) - 0.5 * AXIAL_LENGTH_M,
                       HELIX_RADIUS_M * math.cos(theta), HELIX_RADIUS_M * math.sin(theta)))
    geoms = "\n".join(
        '      <geom type="capsule" size="%.6g" fromto="%.9g %.9g %.9g %.9g %.9g %.9g"/>'
        % ((FILAMENT_RADIUS_M,) + a + b) for a, b in zip(points, points[1:]))
    return f"""<mujoco model="helix_{pitch_over_radius}">
  <!-- Rodenborn et al., PNAS 110, E338 (2013): R = 6.3 mm, lambda/R = {pitch_over_radius},
       axial length 130 mm, filament radius 0.397 mm; written by make_helices.py. -->
  <option gravity="0 0 0"/>
  <custom>
    <numeric name="ipmc_rft_viscosity_Pa_s" data="1"/>
    <text name="ipmc_rft_coefficients" data="gray_hancock"/>
    <numeric name="ipmc_rft_wavelength_m" data="{pitch_m:.9g}"/>
  </custom>
  <worldbody>
    <body name="helix">
      <freejoint/>
{geoms}
    </body>
  </worldbody>
</mujoco>
"""


def main():
    here = pathlib.Path(__file__).resolve().parent
    for ratio in PITCH_OVER_RADIUS:
        (here / f"rodenborn_{ratio}.xml").write_text(helix_mjcf(ratio))


if __name__ == "__main__":
    main()
