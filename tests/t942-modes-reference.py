"""dtm_modes_lowest and dtm_modes_compare (src/spectral/modes.c,
modes_compare.c) on a real Gmsh mesh against an independent assembly.

The model: a free steel bar 0.2 x 0.04 x 0.02 m meshed by Gmsh into linear
tetrahedra (about 260 nodes), analysed by the Python module; dtmap's
operator and its modes through libdtmap's C API (ctypes). The reference
(tests/reference/modes_ref.py) reads the same mesh's nodes and tetrahedra from Gmsh, assembles K with its
own tet4 formula (B^T D B V, isotropic D) and the lumped mass rho V / 4 per
node, builds each extra mass itself and solves the dense pencil with
scipy.linalg.eigh; it shares no code with dtmap.

Cases: no extra mass; point masses at the nodes of the last 15 % of the
bar (the diagonal matrix dtm_csr_point_masses builds); a selective-mass
matrix of the form of docs SMS.md, beta_e (W_e - w_e w_e^T / m_e) (x) I_3
per element with beta_e rising along the bar, assembled here; and an added
mass on the y components only (8 m_i), which drops the y-bending mode
below the z-bending one, so that the comparison must match them by MAC
across the swap.

Checks and tolerances:
- 6 rigid modes named in every case (K's null space is the rigid motions
  whatever the mass), their |lambda| below 1e-8 of the largest computed;
- the lowest 10 elastic eigenvalues within 1e-8 relative of the
  reference's: dtmap's Lanczos test (1e-9 on the residual) leaves an error
  of order 1e-18 / gap, the factorisation at the shift's condition (1e6)
  and the two assemblies' rounding about 1e-10, and eigh's error on the
  lowest eigenvalues is eps |K| / lambda, about 1e-12 here;
- each returned residual ||K x - lambda B x|| / (lambda ||B x||) below 1e-7;
- the Sturm check (the inertia of K - s B just above the largest mode)
  counts exactly the modes returned;
- the swap: base modes 0 and 1 matched to modified modes 1 and 0 with a MAC
  above 0.9, each shift within 1e-6 percentage points of the reference's
  (the reference's own MAC matching on its eigenvectors); a modified model
  computed with one elastic mode leaves base mode 0 unmatched (match -1,
  shift NaN).
"""

import ctypes
import math
import os
import sys
import unittest

import gmsh
import numpy
import scipy.sparse

import dtmap
from dtmap._lib import check, lib
import testutil as tu

sys.path.insert(0, os.path.join(tu.SRC, "tests", "reference"))
from modes_ref import Reference, elastic, mac  # noqa: E402

E, NU, RHO = 210e9, 0.3, 7850.0
LX, LY, LZ = 0.2, 0.04, 0.02
NMODES = 10
REL = 1e-8


class Mode(ctypes.Structure):
    _fields_ = [("lam", ctypes.c_double), ("freq", ctypes.c_double), ("residual", ctypes.c_double),
                ("rigid", ctypes.c_int)]


class Modes(ctypes.Structure):
    _fields_ = [("n", ctypes.c_int), ("nrigid", ctypes.c_int), ("nelastic", ctypes.c_int),
                ("mode", ctypes.POINTER(Mode)), ("shape", ctypes.POINTER(ctypes.c_double)), ("ndof", ctypes.c_size_t),
                ("sigma", ctypes.c_double), ("block", ctypes.c_int), ("steps", ctypes.c_int),
                ("converged", ctypes.c_int), ("seconds", ctypes.c_double), ("factor_seconds", ctypes.c_double),
                ("sturm_at", ctypes.c_double), ("sturm", ctypes.c_long), ("counted", ctypes.c_int)]


class Csr(ctypes.Structure):
    _fields_ = [("n", ctypes.c_size_t), ("rowptr", ctypes.POINTER(ctypes.c_size_t)),
                ("col", ctypes.POINTER(ctypes.c_size_t)), ("val", ctypes.POINTER(ctypes.c_double))]


class Shift(ctypes.Structure):
    _fields_ = [("base", ctypes.c_int), ("match", ctypes.c_int), ("mac", ctypes.c_double),
                ("shift", ctypes.c_double)]


lib.dtm_analysis_operator.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_double, ctypes.POINTER(ctypes.c_void_p)]
lib.dtm_modes_lowest.argtypes = [ctypes.c_void_p, ctypes.POINTER(Csr), ctypes.c_int, ctypes.POINTER(Modes)]
lib.dtm_modes_free.argtypes = [ctypes.POINTER(Modes)]
lib.dtm_modes_compare.argtypes = [ctypes.c_void_p, ctypes.POINTER(Modes), ctypes.POINTER(Modes), ctypes.POINTER(Shift)]
lib.dtm_csr_point_masses.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_double), ctypes.c_size_t,
                                     ctypes.POINTER(Csr)]
lib.dtm_csr_free.argtypes = [ctypes.POINTER(Csr)]
lib.dtm_operator_destroy.argtypes = [ctypes.POINTER(ctypes.c_void_p)]
lib.dtm_operator_ndof.argtypes = [ctypes.c_void_p]
lib.dtm_operator_ndof.restype = ctypes.c_size_t


# ---- dtmap through the C API --------------------------------------------------

class Dtmap:
    def __init__(self, result, ref):
        self.result = result
        self.op = ctypes.c_void_p()
        check(lib.dtm_analysis_operator(result._analysis, 0, 0.0, ctypes.byref(self.op)))
        self.n = lib.dtm_operator_ndof(self.op)
        # dtmap's unknown j is the reference's perm[j]
        node_ref = numpy.array([ref.pos[int(t)] for t in result.node_tags])
        self.perm = (3 * node_ref[:, None] + numpy.arange(3)[None, :]).ravel()
        self.kept = []

    def csr(self, dense_ref):
        """A matrix of the reference's numbering as a dtm_csr in dtmap's."""
        a = scipy.sparse.csr_matrix(dense_ref[numpy.ix_(self.perm, self.perm)])
        a.sort_indices()
        rowptr = numpy.ascontiguousarray(a.indptr, dtype=numpy.uintp)
        col = numpy.ascontiguousarray(a.indices, dtype=numpy.uintp)
        val = numpy.ascontiguousarray(a.data, dtype=numpy.float64)
        self.kept += [rowptr, col, val]
        return Csr(self.n, rowptr.ctypes.data_as(ctypes.POINTER(ctypes.c_size_t)),
                   col.ctypes.data_as(ctypes.POINTER(ctypes.c_size_t)),
                   val.ctypes.data_as(ctypes.POINTER(ctypes.c_double)))

    def modes(self, extra=None, n=NMODES):
        out = Modes()
        code = lib.dtm_modes_lowest(self.op, ctypes.byref(extra) if extra is not None else None, n,
                                    ctypes.byref(out))
        assert code == 0, "dtm_modes_lowest failed: %d" % code
        return out

    def close(self):
        lib.dtm_operator_destroy(ctypes.byref(self.op))


class ModesReference(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        gmsh.initialize(["t942", "-v", "0"])
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.model.add("bar")
        gmsh.model.occ.addBox(0, 0, 0, LX, LY, LZ)
        gmsh.model.occ.synchronize()
        gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [1]), "bar")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.012)
        gmsh.model.mesh.generate(3)
        gmsh.write(tu.path("bar.msh"))
        cls.ref = Reference(E, NU, RHO)
        cls.result = dtmap.analyse(materials={"steel": {"groups": "bar", "E": E, "nu": NU, "rho": RHO}},
                                   effects=["elastic"], views=False)
        cls.dt = Dtmap(cls.result, cls.ref)

    @classmethod
    def tearDownClass(cls):
        cls.dt.close()
        cls.result.close()
        gmsh.finalize()

    def check_against(self, md, values, what):
        self.assertTrue(md.converged, what)
        self.assertEqual((md.counted, md.sturm), (1, md.n), what + ": the Sturm count")
        self.assertEqual(md.nrigid, 6, what)
        self.assertEqual(md.nelastic, NMODES, what)
        top = md.mode[md.n - 1].lam
        for i in range(6):
            self.assertTrue(md.mode[i].rigid, what)
            self.assertLessEqual(abs(md.mode[i].lam), 1e-8 * top, what)
        want = elastic(values)[0]
        worst = 0
        for i in range(NMODES):
            got = md.mode[6 + i]
            self.assertFalse(got.rigid, what)
            self.assertLessEqual(got.residual, 1e-7, what)
            rel = abs(got.lam - want[i]) / want[i]
            worst = max(worst, rel)
            self.assertLessEqual(rel, REL, "%s mode %d: %.12g Hz against %.12g Hz" % (
                what, i, got.freq, math.sqrt(want[i]) / (2 * math.pi)))
        print("%s: f = %.2f .. %.2f Hz, worst relative eigenvalue error %.2g, %d steps, sigma %.3g" % (
            what, md.mode[6].freq, md.mode[md.n - 1].freq, worst, md.steps, md.sigma))

    def test_plain(self):
        md = self.dt.modes()
        self.check_against(md, self.ref.eig()[0], "no extra mass")
        lib.dtm_modes_free(ctypes.byref(md))

    def test_point_masses(self):
        ref = self.ref
        kg_ref = numpy.where(ref.x[:, 0] > 0.85 * LX, 0.004, 0.0)
        kg = numpy.ascontiguousarray([kg_ref[ref.pos[int(t)]] for t in self.result.node_tags], dtype=numpy.float64)
        csr = Csr()
        check(lib.dtm_csr_point_masses(self.dt.op, kg.ctypes.data_as(ctypes.POINTER(ctypes.c_double)),
                                               len(kg), ctypes.byref(csr)))
        md = self.dt.modes(csr)
        self.check_against(md, ref.eig(numpy.diag(numpy.repeat(kg_ref, 3)))[0], "point masses")
        lib.dtm_modes_free(ctypes.byref(md))
        lib.dtm_csr_free(ctypes.byref(csr))

    def test_selective(self):
        S = self.ref.sms(lambda c: 1 + 4 * c[0] / LX)
        md = self.dt.modes(self.dt.csr(S))
        self.check_against(md, self.ref.eig(S)[0], "selective mass")
        lib.dtm_modes_free(ctypes.byref(md))

    def test_swap(self):
        ref = self.ref
        Y = numpy.diag(numpy.where(numpy.arange(len(ref.m)) % 3 == 1, 8 * ref.m, 0.0))
        base_v, base_x = elastic(*ref.eig())
        mod_v, mod_x = elastic(*ref.eig(Y))
        base, mod = self.dt.modes(), self.dt.modes(self.dt.csr(Y))
        self.check_against(mod, ref.eig(Y)[0], "y mass")
        sh = (Shift * NMODES)()
        check(lib.dtm_modes_compare(self.dt.op, ctypes.byref(base), ctypes.byref(mod), sh))
        self.assertEqual((sh[0].match, sh[1].match), (1, 0), "the first two modes swap")
        for i in range(2):
            self.assertGreater(sh[i].mac, 0.9)
            j = max(range(NMODES), key=lambda j: mac(base_x[:, i], mod_x[:, j], ref.m))
            self.assertEqual(j, sh[i].match)
            want = 100 * (math.sqrt(mod_v[j] / base_v[i]) - 1)
            self.assertLessEqual(abs(sh[i].shift - want), 1e-6, "mode %d: %g %% against %g %%" % (i, sh[i].shift, want))
            print("base mode %d (%.1f Hz) -> modified mode %d: MAC %.4f, shift %+.3f %% (reference %+.3f %%)" % (
                i, base.mode[6 + i].freq, sh[i].match, sh[i].mac, sh[i].shift, want))
        one = self.dt.modes(self.dt.csr(Y), 1)
        sh1 = (Shift * NMODES)()
        check(lib.dtm_modes_compare(self.dt.op, ctypes.byref(base), ctypes.byref(one), sh1))
        self.assertEqual(sh1[0].match, -1, "the z-bending mode is above the one modified mode computed")
        self.assertTrue(math.isnan(sh1[0].shift))
        self.assertLess(sh1[0].mac, 0.8)
        self.assertEqual(sh1[1].match, 0)
        for m in (base, mod, one):
            lib.dtm_modes_free(ctypes.byref(m))


if __name__ == "__main__":
    tu.main()
