"""Readers for planetwear's output: simulation files (xarray), campaign
archives (pandas) and diagnosis reports (dict). Documentation:
docs/postprocessing.md; the file layouts: docs/output-format.md,
docs/archive-format.md, docs/diagnose.md.

    from planetwear import load_simulation, load_campaign, load_diagnosis
"""
from ._hdf5 import FormatError
from .campaign import CampaignResults, load_campaign
from .diagnosis import load_diagnosis
from .simulation import load_simulation, load_wear_snapshots

__version__ = "0.1.0"  # = project(planetwear VERSION ...) in CMakeLists.txt (tested)

__all__ = ["load_simulation", "load_wear_snapshots", "load_campaign", "CampaignResults", "load_diagnosis",
           "FormatError", "__version__"]
