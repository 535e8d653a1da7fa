"""dtmap for Gmsh scripts: the critical explicit time step of the current
Gmsh model, in the same process as ``import gmsh``.

Build or open a model with Gmsh's Python API, mesh it, then::

    import dtmap
    r = dtmap.analyse(materials={"steel": {"groups": "solid", "E": 210e9, "nu": 0.3, "rho": 7850}},
                      effects=["elastic"])
    print(r.recommended, r.basis)

or ``dtmap.analyse(scene="x.xml")`` to take the materials, sections, effects
and time settings of a scene file (its ``<geometry>`` or ``<mesh>`` is not
opened: the current model is analysed).  The result holds numpy arrays
(element and node tags, element steps, nodal steps, size suggestion), the
recommended step and what it rests on, and the tags of the views dtmap
added to the open Gmsh session (styled as ``dtmap run``'s .opt styles
them), which ``gmsh.fltk.run()`` shows.  Every dtmap error raises
:class:`dtmap.Error` with dtmap's message.  Steps are in s; lengths and
masses in the scene's system of units (``Result.units``: m and kg, or mm
and t under ``<dtmap-scene units="mm-t-s">``).

The module is ctypes over libdtmap (no compiled extension); it needs
Gmsh's Python module on the same libgmsh (Debian: python3-gmsh) and numpy.
"""

import ctypes
import os

import numpy

from ._lib import GLOBAL_BASIS, Error, GMSH_LIBRARY, LIBRARY, Results, check, gmsh, lib
from . import _scene

__all__ = ["analyse", "Result", "Error", "version", "LIBRARY", "GMSH_LIBRARY"]
__version__ = lib.dtm_version().decode()

# dtm_unit (include/dtmap/units.h) of the quantities Result.units names
_UNITS = {"length": 0, "area": 1, "mass": 3, "density": 4, "speed": 5, "modulus": 6}
_VIEWS_MAX = 256  # more views than dtmap ever adds (a few, plus two per effect)


def version():
    """dtmap's version, the Gmsh version libdtmap runs on, and the effect API
    version it loads, as a dict."""
    buf = ctypes.create_string_buffer(64)
    api = ctypes.c_char_p()
    check(lib.dtm_gmsh_version(buf, len(buf), ctypes.byref(api)))
    return {"dtmap": __version__, "gmsh": buf.value.decode(), "gmsh_api": api.value.decode(),
            "effect_api": lib.dtm_registry_api_version()}


def _array(ptr, n, dtype):
    """A numpy copy of n values at ptr (empty when n is 0)."""
    if n == 0:
        return numpy.empty(0, dtype=dtype)
    return numpy.ctypeslib.as_array(ptr, shape=(n,)).astype(dtype, copy=True)


class Result:
    """One analysis of the current Gmsh model.

    Arrays over elements follow dtmap's element order (``element_tags``
    gives each one's Gmsh tag); arrays over nodes follow ``node_tags``.

    - ``element_tags`` [n] uint64, ``dt`` [n] s (each element's own step:
      the minimum over the effects, before the safety factor), ``length``
      [n] (characteristic length of the limiting effect, in ``units["length"]``), ``limiting``
      [n] int (index into ``effects``)
    - ``node_tags`` [m] uint64, ``nodal_dt`` [m] s (the nodal bound; +inf at
      nodes no spectral effect reaches), ``size_suggestion`` [m] in
      ``units["length"]`` (NaN at nodes of no analysed element)
    - ``units``: the scene's system of units and the names of its units,
      {"system": "SI" or "mm-t-s", "length": "m" or "mm", "mass": "kg" or
      "t", "density", "modulus", "speed"}: the unit of every length, mass,
      ... of the result and of the views; the step is in s in both; the
      report of ``write_report`` is in SI (its "units" object says so)
    - ``dt_min`` s and ``dt_min_element`` (Gmsh tag): the element bound;
      ``dt_nodal``, ``dt_global`` s (NaN when not computed);
      ``recommended`` s: safety x the best guaranteed-safe estimate (on the
      global estimate without a deterministic proof, at most the probable
      bound's certified step: the report's lanczos.probable);
      ``basis``: "element bound", "nodal bound" or "global estimate"
    - ``effects``: effect names in scene order; ``views``: view name -> Gmsh
      view tag of the views added to the session (empty with views=False)
    - ``warnings``: the warnings of ``dtmap run``'s summary and report, one
      sentence each, the plausibility ones (a density, wave speed or model
      size that looks like a unit error) first; values no solid has raise
      :class:`dtmap.Error` when the scene is read, as the CLI exits 2

    ``write(path)`` writes the .msh with its views (+ .opt) and
    ``write_report(path)`` the JSON report, as ``dtmap run`` does; both use
    the model as it is, so call them before changing it.  ``close()`` (or
    the garbage collector) frees the C objects; the arrays stay.
    """

    def __init__(self, scene, analysis, cost):
        self._scene, self._analysis, self._cost = scene, analysis, cost
        a = analysis
        n, m = lib.dtm_analysis_nelements(a), lib.dtm_analysis_nnodes(a)
        tags = (ctypes.c_size_t * max(n, 1))()
        lib.dtm_analysis_tags(a, tags)
        self.element_tags = numpy.array(tags[:n], dtype=numpy.uint64)
        self.dt = _array(lib.dtm_analysis_dt(a), n, numpy.float64)
        self.length = _array(lib.dtm_analysis_length(a), n, numpy.float64)
        self.limiting = _array(lib.dtm_analysis_limiting(a), n, numpy.int32)
        self.node_tags = _array(lib.dtm_analysis_node_tags(a), m, numpy.uint64)
        self.nodal_dt = _array(lib.dtm_analysis_nodal(a), m, numpy.float64)
        self.size_suggestion = _array(lib.dtm_analysis_size_suggestion(a), m, numpy.float64)
        where = ctypes.c_size_t()
        self.dt_min = lib.dtm_analysis_dt_min(a, ctypes.byref(where))
        self.dt_min_element = int(self.element_tags[where.value]) if n else None
        self.dt_nodal = lib.dtm_analysis_dt_nodal(a)
        self.dt_global = lib.dtm_analysis_dt_global(a)
        self.recommended = lib.dtm_analysis_recommended(a)
        self.basis = lib.dtm_analysis_basis(a).decode()
        self.effects = [lib.dtm_analysis_effect(a, k).contents.name.decode()
                        for k in range(lib.dtm_analysis_neffects(a))]
        self.views = {}
        system = lib.dtm_scene_units(scene)
        self.units = {"system": system.decode()}
        for name, q in _UNITS.items():
            self.units[name] = lib.dtm_units_name(system, q).decode()
        self.warnings = self._warnings()

    def _warnings(self):
        res = self._results()
        buf = ctypes.create_string_buffer(1 << 16)
        lib.dtm_output_warning_lines(ctypes.byref(res), buf, len(buf))
        return [w for w in buf.value.decode(errors="replace").split("\n") if w]

    def _results(self):
        if self._analysis is None:
            raise Error("this dtmap result was closed", 3)
        return Results(self._analysis.value, self._cost.value, None, 0.0, 0.0, 0)

    def add_views(self):
        """Add dtmap's views to the current model of the Gmsh session; returns
        {view name: view tag}."""
        res = self._results()
        tags = (ctypes.c_int * _VIEWS_MAX)()
        count = ctypes.c_int()
        check(lib.dtm_output_add_views(ctypes.byref(res), tags, _VIEWS_MAX, ctypes.byref(count)))
        for t in tags[:count.value]:
            self.views[gmsh.option.getString("View[%d].Name" % gmsh.view.getIndex(t))] = t
        return self.views

    def write(self, path):
        """Write the analysed mesh with its views to path (.msh) and path.opt."""
        res = self._results()
        check(lib.dtm_output_write(ctypes.byref(res), os.fsencode(path)))

    def write_report(self, path):
        """Write the JSON report (schema: share/dtmap/dtmap-report.schema.json)."""
        res = self._results()
        check(lib.dtm_report_write(ctypes.byref(res), os.fsencode(path)))

    def close(self):
        """Free the C objects (the arrays stay)."""
        if self._analysis is not None:
            lib.dtm_cost_destroy(ctypes.byref(self._cost))
            lib.dtm_analysis_destroy(ctypes.byref(self._analysis))
            lib.dtm_scene_destroy(ctypes.byref(self._scene))
            self._analysis = None

    def __del__(self):
        self.close()

    def __repr__(self):
        return "<dtmap.Result: %d elements, recommended %.4e s (%s)>" % (len(self.dt), self.recommended, self.basis)


def _load_scene(scene, text):
    """The scene file, or the generated text, as a C handle on the current model."""
    handle = ctypes.c_void_p()
    if scene is not None:
        check(lib.dtm_scene_load(os.fsencode(scene), ctypes.byref(handle)))
        check(lib.dtm_scene_use_model(handle))
        return handle
    data = text.encode()
    check(lib.dtm_scene_load_memory(data, len(data), _scene.NAME.encode(), ctypes.byref(handle)))
    return handle


def _analyse(scene, dim, threads, posterior, tol, lanczos_max):
    check(lib.dtm_gmsh_attach(threads))
    d = ctypes.c_int(dim or 0)
    if not dim:
        check(lib.dtm_gmsh_model_dim(scene, ctypes.byref(d)))
    analysis, cost = ctypes.c_void_p(), ctypes.c_void_p()
    try:
        check(lib.dtm_analysis_current(scene, d.value, ctypes.byref(analysis)))
        if posterior:
            check(lib.dtm_analysis_estimate_global(analysis, tol, lanczos_max, GLOBAL_BASIS))  # as run --posterior
        check(lib.dtm_cost_create(analysis, ctypes.byref(cost)))
    except Error:
        lib.dtm_cost_destroy(ctypes.byref(cost))
        lib.dtm_analysis_destroy(ctypes.byref(analysis))
        raise
    return analysis, cost


def analyse(scene=None, *, materials=None, effects=None, time=None, meshing=None, sections=None, dim=None,
            threads=0, posterior=False, tol=1e-4, lanczos_max=400, views=True):
    """Analyse the current Gmsh model (already meshed) and return a Result.

    scene: a scene file for the materials, effects and <time>; or instead
      materials: {name: {"groups": "a b" or [...], "E": ..., "nu": ..., "rho": ..., ...}}
        ("default": True for elements in no named group);
      effects: ["elastic", ("damping", {"xi": 0.05}), {"name": "cohesive", "groups": "rock"}, ...];
      time: {"safety": 0.9, "target": ..., "duration": ..., "f_max": ...};
      meshing: {"dim": 2} to choose the dimension analysed;
      sections: [{"groups": "rebar", "kind": "truss", "area": 3.1e-4}, ...], the scene's
        <section> attributes ("default": True for the elements in no sectioned group;
        shear_factor for shear-factor).
    dim: the dimension to analyse (default: the scene's <meshing dim>, else
      the model's). threads: OpenMP threads for dtmap (0: all cores).
    posterior: also the global (Lanczos) estimate, to relative residual tol
      in at most lanczos_max steps, as `dtmap run --posterior`.
    views: add dtmap's views to the Gmsh session.
    """
    text = None
    if scene is None:
        text = _scene.scene_text(materials, effects, time, meshing, sections)
    elif materials or effects or time or meshing or sections:
        raise ValueError("dtmap.analyse: give either scene= or materials=/effects=/time=/meshing=/sections=")
    handle = ctypes.c_void_p()
    try:
        handle = _load_scene(scene, text)
        analysis, cost = _analyse(handle, dim, threads, posterior, tol, lanczos_max)
    except Error as e:
        lib.dtm_scene_destroy(ctypes.byref(handle))
        raise Error(_scene.annotate(str(e), text or ""), e.code) from None
    result = Result(handle, analysis, cost)
    if views:
        result.add_views()
    return result
