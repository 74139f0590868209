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
    PlantTrace,
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


def to_json(obj):
    """A result as JSON values: NumPy arrays as lists, complex numbers as [re, im] (the CLI's form).

    ``json.dumps(gmslab.to_json(gmslab.design(...)))`` is what ``gmslab design --json`` writes."""
    import numpy as np
    if isinstance(obj, dict):
        return {k: to_json(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_json(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return to_json(obj.tolist())
    if isinstance(obj, (complex, np.complexfloating)):
        return [float(obj.real), float(obj.imag)]
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


__all__ = [
    "InputError", "InternalError", "IoError", "Model", "ModelParams", "Plant", "PlantTrace", "RunSettings",
    "Scenario", "SimulationError", "Trace", "design", "figure", "figure_ids", "identify",
    "load_record", "load_scenario", "load_trace", "to_json", "models", "root_locus", "save_scenario", "simulate",
]
