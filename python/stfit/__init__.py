"""stfit: rough-glass appearance from Python.

Microfacet NDFs (Beckmann, GGX, Student-T) with exact visible-normal sampling, the rough
dielectric of Walter et al. 2007, the multiple-scattering random walk, fits of these models to
measured scattering, synthetic measurements and comparison reports. Every call runs the Rust
library crates of stfit (the same code as the ``stfit`` command line) on NumPy arrays, with the
GIL released and on all cores for large batches.

Conventions: the local frame has the macro-surface normal along +z; the outside (z > 0) has
index 1 and the inside index ``eta``. Directions are unit vectors of shape ``(..., 3)``
pointing away from the surface, ``wi`` toward the light. NDFs are normalised by projected
area. ``eval(wi, wo)`` returns ``f(wi, wo) |wo.z|`` with ``f`` the BSDF of Walter et al. 2007.

>>> import stfit
>>> data = stfit.load("fits/example.csv")                      # doctest: +SKIP
>>> fits = stfit.fit(data, model="all")                        # doctest: +SKIP
>>> print(stfit.table(fits))                                   # doctest: +SKIP
"""

from ._stfit import (
    Albedo,
    Beckmann,
    BsdfSamples,
    Dataset,
    ExportError,
    FitError,
    FitResult,
    Ggx,
    LoadError,
    LongRunWarning,
    Microsurface,
    RoughDielectric,
    StudentT,
    Table,
    __version__,
    export,
    fit,
    fits_json,
    load,
    read_fits,
    report,
    merge_table_shards,
    synth,
    table,
    table_shard,
    table_spec,
    tables,
)

__all__ = [
    "Albedo",
    "Beckmann",
    "BsdfSamples",
    "Dataset",
    "ExportError",
    "FitError",
    "FitResult",
    "Ggx",
    "LoadError",
    "LongRunWarning",
    "Microsurface",
    "RoughDielectric",
    "StudentT",
    "Table",
    "__version__",
    "export",
    "fit",
    "fits_json",
    "load",
    "read_fits",
    "report",
    "merge_table_shards",
    "synth",
    "table",
    "table_shard",
    "table_spec",
    "tables",
]
