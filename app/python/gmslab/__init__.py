"""gmslab: GMS friction simulation, compensation design and identification from Python.

The compiled core (``_gmslab``) runs the same C++ jobs as the ``gmslab`` command line and window.
Units are SI throughout: time [s], position [m], velocity [m/s], force [N].

    import gmslab
    sc = gmslab.load_scenario("presets/fig2a_presliding.json")
    tr = gmslab.simulate(sc)            # tr.t [s], tr.x [m], tr.friction [N] as NumPy arrays

Errors from the core raise gmslab.InputError (a ValueError), gmslab.SimulationError or
gmslab.IoError, with the core's message (file, key path, allowed range).
"""
from ._gmslab import (  # noqa: F401
    InputError,
    InternalError,
    IoError,
    Model,
    ModelParams,
    Plant,
    RunSettings,
    Scenario,
    SimulationError,
    Trace,
    design,
    figure,
    figure_ids,
    identify,
    load_record,
    load_trace,
    load_scenario,
    models,
    root_locus,
    save_scenario,
    simulate,
)

__all__ = [
    "InputError", "InternalError", "IoError", "Model", "ModelParams", "Plant", "RunSettings",
    "Scenario", "SimulationError", "Trace", "design", "figure", "figure_ids", "identify",
    "load_record", "load_scenario", "load_trace", "models", "root_locus", "save_scenario", "simulate",
]
