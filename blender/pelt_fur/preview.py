"""`pelt view` on an exported file: one window per output path, kept open; pelt view reloads
the file when it changes, so a later export of the same path updates that window."""

import subprocess

_windows = {}


def show(pelt, path):
    """Opens `pelt view PATH` unless a window on it is still open; an error string or None."""
    window = _windows.get(path)
    if window is not None and window.poll() is None:
        return None
    try:
        _windows[path] = subprocess.Popen([pelt, "view", path])
    except OSError as e:
        return f"pelt view could not start: {e}"
    return None
