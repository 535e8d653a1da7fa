"""Loading libdtmap with ctypes, next to Gmsh's own Python module.

dtmap works on the model of the Gmsh session a script opened with
``import gmsh``, so both must run on one and the same libgmsh in the
process: two copies would hold two unrelated sets of models.  This module
finds libdtmap (``DTMAP_LIBRARY``, else the path written at install time in
``_install.py``, else the loader's search), imports ``gmsh`` first, loads
libdtmap, and then checks in ``/proc/self/maps`` that a single libgmsh file
is mapped.  It declares the C prototypes the package uses and turns a
non-zero dtmap return code into :class:`Error`.
"""

import ctypes
import ctypes.util
import os

try:
    import gmsh  # Debian: python3-gmsh
except ImportError as e:  # pragma: no cover - exercised only without gmsh
    raise ImportError("dtmap needs Gmsh's Python module (Debian: apt install python3-gmsh): %s" % e)


class Error(Exception):
    """A dtmap error: ``str(e)`` is dtmap's message (naming the file and
    line, or the Gmsh element tag and physical group); ``code`` is dtmap's
    code (1 target not met, 2 bad input, 3 internal error)."""

    def __init__(self, message, code=2):
        super().__init__(message)
        self.code = code


def _library_path():
    env = os.environ.get("DTMAP_LIBRARY")
    if env:
        return env
    try:
        from . import _install  # written by `cmake --install`
        here = os.path.dirname(os.path.abspath(__file__))
        candidate = os.path.normpath(os.path.join(here, _install.LIBRARY))
        if os.path.exists(candidate):
            return candidate
    except ImportError:
        pass
    found = ctypes.util.find_library("dtmap")
    if found:
        return found
    raise ImportError("dtmap: cannot find libdtmap (install dtmap, or set DTMAP_LIBRARY to libdtmap.so.N)")


def mapped_gmsh(maps_file="/proc/self/maps"):
    """Distinct libgmsh files mapped into this process (from its memory map)."""
    found = set()
    with open(maps_file) as maps:
        for line in maps:
            fields = line.split(None, 5)  # address perms offset dev inode [path]
            path = fields[5].strip() if len(fields) == 6 else ""
            if os.path.basename(path).startswith("libgmsh"):
                found.add(os.path.realpath(path))
    return sorted(found)


LIBRARY = _library_path()
lib = ctypes.CDLL(LIBRARY)
_gmsh_files = mapped_gmsh()
if len(_gmsh_files) != 1:
    raise ImportError("dtmap and Gmsh's Python module must share one libgmsh, but this process maps %s "
                      "(gmsh.py loaded %s, libdtmap is %s)" % (_gmsh_files or "none", gmsh.libpath, LIBRARY))
GMSH_LIBRARY = _gmsh_files[0]

_p = ctypes.c_void_p
_size = ctypes.c_size_t
_dbl = ctypes.POINTER(ctypes.c_double)


class EffectClass(ctypes.Structure):
    """The leading fields of dtm_effect_class (include/dtmap/effect.h)."""
    _fields_ = [("api_version", ctypes.c_int), ("name", ctypes.c_char_p), ("summary", ctypes.c_char_p)]


class Results(ctypes.Structure):
    """dtm_results (include/dtmap/output.h)."""
    _fields_ = [("analysis", _p), ("cost", _p), ("refine", _p), ("t_scene", ctypes.c_double),
                ("t_output", ctypes.c_double), ("top", ctypes.c_int), ("nsolvers", ctypes.c_int),
                ("solver_names", _p * 8), ("solver_runs", _p * 8), ("modes", _p), ("selective_mass", _p)]


# dtm_analysis_estimate_global's flags (include/dtmap/analysis.h)
GLOBAL_MODES = 1
GLOBAL_BASIS = 2


_PROTOTYPES = {
    # name: (return type, argument types)
    "dtm_version": (ctypes.c_char_p, []),
    "dtm_registry_api_version": (ctypes.c_int, []),
    "dtm_registry_count": (ctypes.c_int, []),
    "dtm_registry_get": (ctypes.POINTER(EffectClass), [ctypes.c_int]),
    "dtm_gmsh_version": (ctypes.c_int, [ctypes.c_char_p, _size, ctypes.POINTER(ctypes.c_char_p)]),
    "dtm_gmsh_attach": (ctypes.c_int, [ctypes.c_int]),
    "dtm_gmsh_model_dim": (ctypes.c_int, [_p, ctypes.POINTER(ctypes.c_int)]),
    "dtm_error_message": (ctypes.c_char_p, []),
    "dtm_error_code": (ctypes.c_int, []),
    "dtm_error_clear": (None, []),
    "dtm_scene_load": (ctypes.c_int, [ctypes.c_char_p, ctypes.POINTER(_p)]),
    "dtm_scene_load_memory": (ctypes.c_int, [ctypes.c_char_p, _size, ctypes.c_char_p, ctypes.POINTER(_p)]),
    "dtm_scene_use_model": (ctypes.c_int, [_p]),
    "dtm_scene_destroy": (None, [ctypes.POINTER(_p)]),
    "dtm_scene_units": (ctypes.c_char_p, [_p]),
    "dtm_units_name": (ctypes.c_char_p, [ctypes.c_char_p, ctypes.c_int]),
    "dtm_analysis_current": (ctypes.c_int, [_p, ctypes.c_int, ctypes.POINTER(_p)]),
    "dtm_analysis_estimate_global": (ctypes.c_int, [_p, ctypes.c_double, ctypes.c_int, ctypes.c_uint]),
    "dtm_analysis_destroy": (None, [ctypes.POINTER(_p)]),
    "dtm_analysis_nelements": (_size, [_p]),
    "dtm_analysis_nnodes": (_size, [_p]),
    "dtm_analysis_neffects": (ctypes.c_int, [_p]),
    "dtm_analysis_effect": (ctypes.POINTER(EffectClass), [_p, ctypes.c_int]),
    "dtm_analysis_tags": (None, [_p, ctypes.POINTER(_size)]),
    "dtm_analysis_node_tags": (ctypes.POINTER(_size), [_p]),
    "dtm_analysis_dt": (_dbl, [_p]),
    "dtm_analysis_length": (_dbl, [_p]),
    "dtm_analysis_limiting": (ctypes.POINTER(ctypes.c_int), [_p]),
    "dtm_analysis_size_suggestion": (_dbl, [_p]),
    "dtm_analysis_nodal": (_dbl, [_p]),
    "dtm_analysis_dt_min": (ctypes.c_double, [_p, ctypes.POINTER(_size)]),
    "dtm_analysis_dt_nodal": (ctypes.c_double, [_p]),
    "dtm_analysis_dt_global": (ctypes.c_double, [_p]),
    "dtm_analysis_recommended": (ctypes.c_double, [_p]),
    "dtm_analysis_basis": (ctypes.c_char_p, [_p]),
    "dtm_cost_create": (ctypes.c_int, [_p, ctypes.POINTER(_p)]),
    "dtm_cost_destroy": (None, [ctypes.POINTER(_p)]),
    "dtm_output_add_views": (ctypes.c_int, [ctypes.POINTER(Results), ctypes.POINTER(ctypes.c_int), ctypes.c_int,
                                            ctypes.POINTER(ctypes.c_int)]),
    "dtm_output_write": (ctypes.c_int, [ctypes.POINTER(Results), ctypes.c_char_p]),
    "dtm_report_write": (ctypes.c_int, [ctypes.POINTER(Results), ctypes.c_char_p]),
    "dtm_output_warning_lines": (ctypes.c_int, [ctypes.POINTER(Results), ctypes.c_char_p, _size]),
}

for _name, (_res, _args) in _PROTOTYPES.items():
    _f = getattr(lib, _name)
    _f.restype = _res
    _f.argtypes = _args


def check(code):
    """Raise Error with dtmap's pending message when code is not 0."""
    if code == 0:
        return
    message = (lib.dtm_error_message() or b"").decode(errors="replace") or "dtmap error %d" % code
    lib.dtm_error_clear()
    raise Error(message, code)
