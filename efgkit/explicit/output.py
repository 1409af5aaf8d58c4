"""What an explicit run records at its output instants, and its VTU time series.

:class:`Recorder` is built once before the time loop: the probe operators (displacement
and gradient rows at the probe points, one sparse matrix) and, for the VTU series, the
shape functions at the sample grid are evaluated there, so recording is sparse products
only. :class:`VTUSeries` writes ``<name>_<k>.vtu`` files and the ParaView collection
``<name>.pvd`` that orders them in time.
"""

from __future__ import annotations

import time
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np
from scipy.sparse import csr_array, vstack

from ..io import check_finite, pad3, sample_grid, von_mises
from ..problem.material import strain_from_gradient

__all__ = ["Recorder", "VTUSeries"]


class VTUSeries:
    """Fields on :func:`~efgkit.io.sample_grid` at output instants, and the ``.pvd`` index.

    Point data per file: ``displacement``, ``velocity`` (n, 3; z = 0), ``stress`` (n, 3)
    and ``von_mises`` (n,).
    """

    def __init__(self, dyn, directory, name: str, n_target: int = 20000):
        disc = dyn.disc
        scene = disc.scene
        self.dir, self.name = Path(directory), name
        self.x, self.tri = sample_grid(scene.domain, n_target, scene.cracks)
        sh = disc.shape_at(scene.domain.field_points(self.x), derivatives=True)
        self.U = csr_array(vstack(list(sh.u_operators()), format="csr"))
        self.G = csr_array(vstack(list(sh.grad_operators()), format="csr"))
        self.material = scene.material
        self.fE = np.ones(len(self.x)) if scene.grading is None else scene.grading.factors(self.x)[0]
        self.files: list[tuple[float, Path]] = []

    def write(self, t: float, u: np.ndarray, v: np.ndarray) -> Path:
        import meshio

        n = len(self.x)
        disp = (self.U @ u).reshape(2, n).T
        vel = (self.U @ v).reshape(2, n).T
        g = (self.G @ u).reshape(2, 2, n).transpose(2, 0, 1)
        s = self.fE[:, None] * (strain_from_gradient(g) @ self.material.D.T)
        data = {"displacement": pad3(disp), "velocity": pad3(vel), "stress": s,
                "von_mises": von_mises(s, self.material)}
        path = self.dir / f"{self.name}_{len(self.files):05d}.vtu"
        check_finite(data, self.x, path)
        path.parent.mkdir(parents=True, exist_ok=True)
        meshio.write_points_cells(path, pad3(self.x), [("triangle", self.tri)], point_data=data,
                                  compression=None)  # zlib took 0.3 s a file
        self.files.append((t, path))
        return path

    def close(self) -> Path:
        """Write ``<name>.pvd`` (ParaView: File > Open, then play the time steps)."""
        lines = ['<?xml version="1.0"?>',
                 '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
                 "  <Collection>"]
        lines += [f'    <DataSet timestep="{t!r}" group="" part="0" file={quoteattr(p.name)}/>'
                  for t, p in self.files]
        lines += ["  </Collection>", "</VTKFile>", ""]
        path = self.dir / f"{self.name}.pvd"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("\n".join(lines))
        return path


class Recorder:
    """Collects the histories of a run at its output instants (:meth:`record`)."""

    def __init__(self, dyn, stepping, dt: float, dsif, out=None, name: str | None = None,
                 n_out: int = 1):
        disc = dyn.disc
        self.dyn, self.dt, self.dsif = dyn, dt, dsif
        # output instants whose coefficients are kept for snapshot figures
        k = stepping.snapshots
        self.snap_at = {round((j + 1) * (n_out - 1) / k) for j in range(k)}  # not t = 0 (no stress)
        self.snapshots: list[tuple[float, np.ndarray]] = []
        self.probes = stepping.probe_points
        self.seconds = 0.0
        t0 = time.perf_counter()
        if len(self.probes):
            x = disc.scene.domain.field_points(self.probes)
            sh = disc.shape_at(x, derivatives=True)
            self.P = csr_array(vstack(list(sh.u_operators()) + list(sh.grad_operators()),
                                      format="csr"))  # rows: ux, uy, gxx, gxy, gyx, gyy per probe
            g = disc.scene.grading  # graded: D(x) = modulus(x) D
            self.fE_probes = np.ones(len(x)) if g is None else g.factors(x)[0]
        self.series = None
        if stepping.vtu:
            if out is None:
                raise ValueError("stepping.vtu=True needs an output directory: integrate(..., out=DIR)")
            self.series = VTUSeries(dyn, out, name or disc.scene.name)
        self.rows: dict[str, list] = {k: [] for k in ("t", "step", "kinetic", "strain", "work",
                                                      "balance", "drift", "u", "v", "stress")}
        self.sifs: dict[str, list] = {}
        self.seconds += time.perf_counter() - t0

    def record(self, n, t, u, v_half, Ku, f, work, drift):
        """Record instant ``t_n``: ``u = u^n``, ``v_half = v^{n-1/2}``, ``Ku = K u^n``,
        ``f = f(t_n)``, the time-centred ``work`` up to ``t_{n-1/2}`` and the ``drift`` of the
        modified-energy balance so far. The velocity at ``t_n`` is ``v^{n-1/2} + dt/2 a^n``
        and the acceleration ``a^n = M^-1 (f - K u^n)``, both projected M-orthogonally onto
        ``G v = 0`` with Lagrange constraints: this equals the average of the two staggered
        velocities (and their difference over dt) exactly, the constraint forces included."""
        t0 = time.perf_counter()
        dyn, dt = self.dyn, self.dt
        a = dyn.minv * (f - Ku)
        v = v_half + 0.5 * dt * a
        P = dyn.projection
        if dyn.moving_supports:  # G v = (q(t+dt) - q(t-dt)) / 2dt, G a = its second difference
            qm, q0, qp = (dyn.prescribed(max(t + s * dt, 0.0)) for s in (-1, 0, 1))
            qv, qa = (qp - qm) / (2 * dt), (qp - 2 * q0 + qm) / dt ** 2
        else:
            qv = qa = 0.0
        if P is not None:  # = (v^{n-1/2} + v^{n+1/2}) / 2 and (v^{n+1/2} - v^{n-1/2}) / dt exactly
            v = v - P.minv_GT @ P.lu.solve(P.G @ v - qv)
            a = a - P.minv_GT @ P.lu.solve(P.G @ a - qa)
        elif dyn.moving_supports:
            v[dyn.fixed], a[dyn.fixed] = qv, qa
        r = self.rows
        kin = 0.5 * float(v @ (dyn.m * v))
        strain = 0.5 * float(u @ Ku)
        r["t"].append(t)
        r["step"].append(n)
        r["kinetic"].append(kin)
        r["strain"].append(strain)
        r["work"].append(work)
        r["balance"].append(kin + strain - work)
        r["drift"].append(drift)
        if len(self.probes):
            k = len(self.probes)
            pu = (self.P @ u).reshape(6, k)
            pv = (self.P[: 2 * k] @ v).reshape(2, k)
            g = pu[2:].reshape(2, 2, k).transpose(2, 0, 1)
            r["u"].append(pu[:2].T)
            r["v"].append(pv.T)
            r["stress"].append(self.fE_probes[:, None] * (strain_from_gradient(g)
                                                          @ dyn.disc.scene.material.D.T))
        if self.dsif is not None and dyn.disc.scene.tips:
            for key, val in self.dsif(dyn, u, v, a, t).items():
                self.sifs.setdefault(key, []).append(np.asarray(val, float))
        if self.series is not None:
            self.series.write(t, u, v)
        if len(r["t"]) - 1 in self.snap_at:
            self.snapshots.append((t, u.copy()))
        self.seconds += time.perf_counter() - t0

    def arrays(self) -> dict:
        """The histories as arrays: ``t, step, kinetic, strain, work, balance (kinetic +
        strain - work), drift (n_out,)``, probe ``u, v
        (n_out, n_probes, 2)``, ``stress (n_out, n_probes, 3)``, ``sifs`` {estimate:
        (n_out, n_tips, 2)}, ``probes (n_probes, 2)`` and ``vtu`` (the .pvd path or None)."""
        r = self.rows
        k = len(self.probes)
        out = {key: np.asarray(r[key], float) for key in ("t", "kinetic", "strain", "work", "balance",
                                                               "drift")}
        out["step"] = np.asarray(r["step"], int)
        for key, width in (("u", 2), ("v", 2), ("stress", 3)):
            out[key] = np.asarray(r[key], float).reshape(len(r["t"]), k, width)
        out["sifs"] = {key: np.asarray(val) for key, val in self.sifs.items()}
        out["probes"] = self.probes
        out["vtu"] = self.series.close() if self.series is not None else None
        out["snapshots"] = self.snapshots
        return out
