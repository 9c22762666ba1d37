"""Small h5py helpers shared by the loaders."""
import h5py
import numpy as np


class FormatError(ValueError):
    """The file is not the kind of planetwear file the loader expects."""


def text(value):
    """An attribute or string-dataset value as str (h5py returns bytes for
    fixed-length strings, str for variable-length ones)."""
    if isinstance(value, bytes):
        return value.decode("utf-8")
    if isinstance(value, np.ndarray) and value.ndim == 0:
        return text(value[()])
    return str(value)


def unit(obj, default="1"):
    """The unit of a dataset or group: `units` (CF), else `unit` (files
    written before `units` was added), else `default`."""
    for key in ("units", "unit"):
        if key in obj.attrs:
            return text(obj.attrs[key])
    return default


def description(obj):
    return text(obj.attrs["description"]) if "description" in obj.attrs else ""


def datasets_below(group):
    """{relative name: dataset} of every dataset below `group`, in name order."""
    out = {}
    group.visititems(lambda name, obj: out.__setitem__(name, obj) if isinstance(obj, h5py.Dataset) else None)
    return dict(sorted(out.items()))


def read_strings(dataset):
    """A string dataset as a numpy array of str."""
    return np.asarray(dataset.asstr()[()], dtype=object)


def open_checked(path, expected_format, newest_version):
    """Opens `path` read-only after checking its root attributes `format`
    and `format_version` (a newer version may have moved things this
    reader would then misread)."""
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise FormatError(f"{path}: cannot open as HDF5: {exc}") from exc
    found = text(f.attrs.get("format", ""))
    version = int(f.attrs.get("format_version", 0))
    if found != expected_format or version > newest_version:
        f.close()
        raise FormatError(f"{path}: format {found!r} version {version}; this reader reads {expected_format!r} "
                          f"up to version {newest_version}")
    return f
