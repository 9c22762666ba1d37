#!/usr/bin/env python3
"""A simulation file into xarray and a figure: the sun-planet mesh deflection
of every planet over time, and the mesh-line acceleration spectrum up to the
40th mesh harmonic.

    /usr/bin/python3 examples/simulation_plot.py run.h5 [-o run.png]

(run.h5 from `planetwear simulate -o run.h5`; docs/output-format.md.)
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))

import matplotlib  # noqa: E402

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt  # noqa: E402

from planetwear import load_simulation  # noqa: E402


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("file", help="HDF5 file of planetwear simulate")
    p.add_argument("-o", "--output", help="PNG to write (default: the file name with .png)")
    args = p.parse_args(argv)
    output = args.output or os.path.splitext(args.file)[0] + ".png"

    ds = load_simulation(args.file)
    deflection = ds.sun_planet_deflection * 1e6  # m -> µm for the axis
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6), constrained_layout=True)
    deflection.plot.line(x="time", hue="planet", ax=top)  # one line per planet, labelled by xarray
    top.set(ylabel="sun-planet deflection [µm]", xlabel="time [s]")
    # The first 40 mesh harmonics: where the mesh excitation and its sidebands are.
    mesh_frequency = float(ds.mesh_frequency)
    spectrum = ds.sun_planet_acceleration_spectrum.sel(planet=0, frequency=slice(0, 40 * mesh_frequency))
    spectrum.plot(ax=bottom)
    bottom.axvline(mesh_frequency, color="0.6", ls="--", label=f"mesh frequency {mesh_frequency:.1f} Hz")
    bottom.set(xlabel="frequency [Hz]", ylabel=f"amplitude [{spectrum.attrs['units']}]",
               title="sun-planet mesh-line acceleration, planet 0")
    bottom.legend()
    fig.savefig(output, dpi=120)
    print(f"{output}: {ds.sizes['planet']} planets, {ds.sizes['time']} samples, "
          f"max deflection {float(deflection.max()):.3f} µm")
    return 0


if __name__ == "__main__":
    sys.exit(main())
