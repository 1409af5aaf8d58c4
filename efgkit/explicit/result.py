"""The result of an explicit run: histories at the output instants and the final state."""

from __future__ import annotations

import textwrap
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..solution import method_record

__all__ = ["DynamicSolution"]

# sifs entries that are not (K_I, K_II): their two columns (explicit.dsif.DYNAMIC_ESTIMATES)
_COLUMNS = {"J_prime": ("J1", "J2"), "spread": ("J", "interaction"), "J_prime_domains": ("J1", "J2"),
            "J_decomposed_domains": ("J1_I", "J1_II")}


@dataclass(frozen=True, eq=False)
class DynamicSolution:
    """Histories of an explicit run (:func:`~efgkit.explicit.integrate.integrate`).

    Attributes
    ----------
    dyn : Dynamics
        The assembled system (discretisation, K, M, loads, constraints).
    history : dict
        ``t, kinetic, strain, work, balance, drift (n_out,)``, ``step (n_out,)``, probe
        ``u, v (n_out, n_probes, 2)`` and ``stress (n_out, n_probes, 3)``, ``probes
        (n_probes, 2)``, ``sifs`` {estimate: (n_out, n_tips, 2)} (K_I, K_II per tip;
        ``J_prime``: J'_1, J'_2; ``spread``: of the J' and interaction K over the domains),
        ``vtu`` (the ``.pvd`` file or None).
    state : State
        The final state (restart from it with ``integrate(..., state=...)``).
    info : dict
        ``dt, dt_critical, lambda_max, dt_ratio, steps, first_step, output_every,
        energy_drift, energy_scale, bc, steps_per_second``.
    timings : dict
        Seconds per stage (set-up, ``stable_step``, ``loop``, ``output``, ``total``).
    """

    dyn: object
    history: dict
    state: object
    info: dict
    timings: dict = field(default_factory=dict)

    @property
    def scene(self):
        return self.dyn.disc.scene

    @property
    def method(self):
        return self.dyn.disc.method

    @property
    def t(self) -> np.ndarray:
        return self.history["t"]

    def final(self):
        """The fields at the end of the run, a :class:`~efgkit.meshless_solution.MeshlessSolution`."""
        from .system import solution_at

        return solution_at(self.dyn, self.state.u, self.state.t)

    def sizes(self) -> dict:
        nodes = self.dyn.disc.nodes
        return {"n_nodes": nodes.n, "n_boundary_nodes": int(nodes.boundary.sum()),
                "n_dofs": self.dyn.n_dofs}

    def record(self) -> dict:
        """JSON-ready summary and histories (the keys of ``efgkit run --json`` for a
        dynamic scene): ``scene``, ``method``, sizes, ``timings``, ``time`` (:attr:`info`),
        ``history`` (the arrays as lists; probe and SIF arrays keyed by name)."""
        from .. import io

        h = self.history
        hist = {k: h[k] for k in ("t", "step", "kinetic", "strain", "work", "balance", "drift")}
        hist["probes"] = {"x": h["probes"], "u": h["u"], "v": h["v"], "stress": h["stress"]}
        hist["sifs"] = {"tips": [t.id for t in self.scene.tips],
                        **{k: dict(zip(_COLUMNS.get(k, ("KI", "KII")), (v[..., 0], v[..., 1]),
                                       strict=True)) for k, v in h["sifs"].items()}}
        out = {"scene": self.scene.name, "duration": self.scene.duration,
               "method": {"kind": getattr(self.method, "kind", "efg"), **method_record(self.method)},
               **self.sizes(),
               "timings": dict(self.timings), "time": dict(self.info), "history": hist,
               "vtu": None if h["vtu"] is None else str(h["vtu"])}
        return io.jsonable(out)

    def summary(self) -> str:
        """A few lines for the terminal."""
        i = self.info
        h = self.history
        lines = [f"scene     {self.scene.name}: {i['steps']} steps of dt {i['dt']:.4g} "
                 f"({i['dt_ratio']:.3f} of the critical {i['dt_critical']:.4g}, bc {i['bc']}"
                 + (f", MLPG form {i['form']}" if i.get("form") else "") + "), "
                 f"t = {h['t'][0]:.4g} .. {h['t'][-1]:.4g}",
                 f"nodes     {self.sizes()['n_nodes']}, {self.dyn.n_dofs} dofs; "
                 f"{i['steps_per_second']:.1f} steps/s",
                 f"energy    kinetic {h['kinetic'][-1]:.6e}, strain {h['strain'][-1]:.6e}, "
                 f"work {h['work'][-1]:.6e}; modified-energy balance drift {i['energy_drift']:.2e}"]
        for key, val in h["sifs"].items():
            if key in _COLUMNS:
                continue
            for k, tip in enumerate(self.scene.tips):
                j = int(np.argmax(np.abs(val[:, k, 0])))
                lines.append(f"K {key:<12}{tip.id}: K_I peak {val[j, k, 0]:.5g} at t = {h['t'][j]:.4g}"
                             f", K_II at end {val[-1, k, 1]:.5g}")
        t = self.timings
        stages = ", ".join(f"{k} {v:.3f}" for k, v in t.items() if k != "total")
        lines.append(textwrap.fill(f"timings   total {t['total']:.2f} s: {stages} (s)", width=96,
                                   subsequent_indent=" " * 10))
        return "\n".join(lines)

    def plot_history(self):
        """Energies, probe displacements and SIF histories against time; returns the figure."""
        import matplotlib.pyplot as plt

        h = self.history
        n = 1 + (len(h["probes"]) > 0) + (len(h["sifs"]) > 0)
        fig, axes = plt.subplots(n, 1, figsize=(7, 2.6 * n), sharex=True, squeeze=False)
        ax = axes[0, 0]
        for key in ("kinetic", "strain", "work", "balance"):
            ax.plot(h["t"], h[key], label=key)
        ax.set_ylabel("energy")
        ax.legend(fontsize=8)
        k = 1
        if len(h["probes"]):
            for p in range(len(h["probes"])):
                for c in (0, 1):
                    axes[k, 0].plot(h["t"], h["u"][:, p, c], label=f"u{'xy'[c]} at {h['probes'][p].tolist()}")
            axes[k, 0].set_ylabel("displacement")
            axes[k, 0].legend(fontsize=7)
            k += 1
        if len(h["sifs"]):
            for key, val in h["sifs"].items():
                if key in _COLUMNS:  # J' and spreads are no K
                    continue
                for j, tip in enumerate(self.scene.tips):
                    axes[k, 0].plot(h["t"], val[:, j, 0], label=f"K_I {key} {tip.id}")
                    axes[k, 0].plot(h["t"], val[:, j, 1], "--", label=f"K_II {key} {tip.id}")
            axes[k, 0].set_ylabel("K")
            axes[k, 0].legend(fontsize=7)
        axes[-1, 0].set_xlabel("t")
        fig.tight_layout()
        return fig

    def write(self, out, name: str | None = None, component: str = "von_mises") -> dict:
        """Write ``<name>.json`` (:meth:`record` with ``outputs``), ``<name>_state.npz``
        (the final state, for restarts), ``<name>_history.png`` and the stress snapshots
        kept by ``Stepping.snapshots`` as ``<name>_stress_<k>.png`` (``component`` of
        :func:`efgkit.plot.plot_stress`). Returns the record."""
        from ..io import file_name, write_figure, write_json
        from .system import solution_at

        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        name = name or file_name(self.scene.name)
        rec = self.record()
        state = out / f"{name}_state.npz"
        self.state.save(state)
        paths = [state, write_figure(self.plot_history(), out / f"{name}_history.png")]
        for k, (t, u) in enumerate(self.history.get("snapshots", [])):
            # a uniform field (before the waves arrive) has an empty colour range
            with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
                fig = solution_at(self.dyn, u, t).plot_stress(component)
                fig.axes[0].set_title(f"{component} stress at t = {t:.4g}")
                paths.append(write_figure(fig, out / f"{name}_stress_{k:03d}.png"))
        if self.history["vtu"] is not None:
            paths.append(Path(self.history["vtu"]))
        rec["outputs"] = [str(p) for p in paths + [out / f"{name}.json"]]
        write_json(rec, out / f"{name}.json")
        return rec
