"""Turning planetwear's '/'-separated HDF5 names into xarray variable names.

A name such as ``sun_planet/2/deflection`` holds one number that indexes a
family of like datasets (here planet 2). The loaders stack such families
along a dimension (``sun_planet_deflection(planet, time)``); this module
finds the index, the family and the dimension's name.
"""
import re

# The path component in front of an index names what the index counts.
# Meshes (sun_planet/<i>, planet_ring/<i>), load shares and load-sharing
# factors count planets; natural frequencies count modes
# (docs/output-format.md).
_INDEX_DIMENSIONS = {
    "sun_planet": "planet",
    "planet_ring": "planet",
    "load_sharing": "planet",
    "load_sharing_factor": "planet",
    "natural_frequency": "mode",
}

_NOT_IDENTIFIER = re.compile(r"[^0-9A-Za-z_]")


def variable_name(name):
    """'sun/speed' -> 'sun_speed': a Python identifier usable as ds.<name>."""
    out = _NOT_IDENTIFIER.sub("_", name.replace("/", "_"))
    return "_" + out if out[:1].isdigit() else out


def split_index(name):
    """('sun_planet/deflection', 'planet', 2) for 'sun_planet/2/deflection'.

    Names with no integer component, or with more than one, are not a
    family member: (name, None, None)."""
    parts = name.split("/")
    positions = [k for k, p in enumerate(parts) if p.isdigit()]
    if len(positions) != 1:
        return name, None, None
    k = positions[0]
    before = parts[k - 1] if k > 0 else ""
    dimension = _INDEX_DIMENSIONS.get(before, variable_name(before) + "_index" if before else "index")
    family = "/".join(parts[:k] + parts[k + 1:])
    return family, dimension, int(parts[k])


_PLANET_FLANK = re.compile(r"^planet_(\d+)/(.+)$")


def split_planet_flank(name):
    """('planet/sun_side', 2) for the wear flank family 'planet_2/sun_side';
    (name, None) for 'sun', 'ring'."""
    m = _PLANET_FLANK.match(name)
    if not m:
        return name, None
    return "planet/" + m.group(2), int(m.group(1))
