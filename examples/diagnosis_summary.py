#!/usr/bin/env python3
"""A diagnosis report read back: the verdict, the fitted parameters and the
data tables behind the plots.

    /usr/bin/python3 examples/diagnosis_summary.py report/

(report/ from `planetwear diagnose -r rec.csv -o report/`; docs/diagnose.md.)
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))

from planetwear import load_diagnosis  # noqa: E402


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("folder", help="output folder of planetwear diagnose")
    args = p.parse_args(argv)

    report = load_diagnosis(args.folder)
    print(f"verdict: {report['verdict']}")
    print(f"missing physics: {report.get('missing_physics') or 'none named'}")
    print(f"speed: {report['speed']['input_rpm']:.2f} rpm ({report['speed']['source']})")
    # The named physics' parameters if one was named, else the recalibrated nuisance.
    fitted = report.get("fitted_parameters") or report["nuisance"]["parameters"]
    print("fitted parameters:")
    for parameter in fitted:
        print(f"  {parameter['name']} = {parameter['value']} ± {parameter['std_error']} {parameter['unit']}")
    print(f"{len(report['data'])} data tables:")
    for name, table in report["data"].items():
        print(f"  {name}: {table.shape[0]} rows, columns {', '.join(table.columns)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
