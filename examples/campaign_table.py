#!/usr/bin/env python3
"""A campaign archive into pandas: the design table joined with the scalar
results, summarized per status and per factor level, and one case's spectrum.

    /usr/bin/python3 examples/campaign_table.py campaign.h5

(campaign.h5 from `planetwear sweep CAMPAIGN.toml -o campaign.h5`;
docs/archive-format.md.)
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))

import pandas as pd  # noqa: E402

from planetwear import load_campaign  # noqa: E402


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("file", help="campaign archive of planetwear sweep")
    args = p.parse_args(argv)

    design, results = load_campaign(args.file)
    table = design.join(results.scalars)  # both indexed by the case
    pd.set_option("display.width", 160)
    print(f"{len(table)} cases:", table["status"].value_counts().to_dict())

    factors = results.campaign["factors"].split(",")
    outputs = [c for c in ("efficiency", "sun_planet/0/acceleration_rms") if c in table]
    print("\nscalar results of the done cases:")
    print(table.loc[table.status == "done", outputs].describe())
    for factor in factors:
        if table[factor].nunique() < len(table):  # a factor with repeated levels: group by it
            print(f"\nmean by {factor} [{design.attrs['units'].get(factor, '')}]:")
            print(table.groupby(factor)[outputs].mean())

    if len(results.done_cases):
        case = int(results.done_cases[0])
        spectrum = results.spectrum("sun_planet/0/acceleration", case)
        peak = spectrum.idxmax("frequency")
        print(f"\ncase {case}: largest sun-planet acceleration amplitude {float(spectrum.max()):.4g} "
              f"{spectrum.attrs['units']} at {float(peak):.1f} Hz")
    return 0


if __name__ == "__main__":
    sys.exit(main())
