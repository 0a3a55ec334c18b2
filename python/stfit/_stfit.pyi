"""Type stubs of stfit's Rust extension (``stfit._stfit``), re-exported by ``stfit``.

Directions are unit vectors in the local frame (+z the macro normal, z > 0 outside with index
1, z < 0 inside with index ``eta``), given as any array-like of shape ``(..., 3)`` of an integer
or float dtype (booleans, complex numbers and text raise ``ValueError``, not converted, and so
does a bool among numbers in nested lists, which NumPy would make 1 or 0); values come back
with the leading shape, or as a float for a single direction of shape ``(3,)``. A
direction with a coordinate that is not finite, whose norm differs from 1 by more than 1e-6, or
whose z is subnormal (nonzero and below 2.2e-308 in magnitude, where 1 / |z| overflows; 0 is the
horizon) raises ``ValueError`` naming the argument and the row. A call checks and computes on
its own copy of the directions, made once with the GIL released: another thread writing into
the array meanwhile changes what the call may see, but never gets an unchecked direction into
it (no panic, no NaN).

Numbers: every numeric argument (``alpha``, ``gamma``, ``eta``, ``scale``, ``noise``,
``log_floor``, ``n``, ``k``, ``absorption``, ``walks``, ``seed``, shard numbers, and the
elements of angle lists, axis lists and ``predict``'s angles) takes a Python int or float or a
NumPy integer or float; a bool (``True``, ``numpy.bool_``, a bool array) raises ``ValueError``
naming the argument (and the element's index), where it would count as 1 or 0; anything else
that is not a number raises ``TypeError`` naming it.

Masked arrays: a ``numpy.ma.MaskedArray`` with a masked element, given as directions, as a
number sequence or as a column of ``load``, raises ``ValueError`` naming the argument and the
first masked index (``LoadError`` at the masked row for a column): its values under the mask
would be used. Fill (``numpy.ma.filled``) or drop (``compressed``) them first; a masked array
with nothing masked is taken as its data.

Values: reprs write numbers as ``repr(float)`` does (``stfit.Ggx(alpha=1e-08)``). NDFs,
``RoughDielectric`` and ``Microsurface`` are immutable parameter objects: equal when of the
same class with equal parameters (and NDFs), hashable consistently with that, and they pickle
as their arguments. ``Dataset``, ``Albedo`` and ``FitResult`` pickle too, every number exactly;
``Dataset`` and ``FitResult`` compare by value and are unhashable.
"""

import os
import pathlib
from typing import Any, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
FloatOrArray = Union[float, npt.NDArray[np.float64]]
PathLike = Union[str, os.PathLike[str]]
DataSource = Union["Dataset", PathLike, Sequence[PathLike], Mapping[str, Any], Any]

class LoadError(ValueError):
    """Bad measurement data.

    ``file``: the file (``<arrays>`` or ``<DataFrame>`` for in-memory columns); ``line``: the
    1-based line (for in-memory columns row k is line k + 2, the header being line 1), or None;
    ``column``: the column's header name, or None; ``message``: what is wrong.
    """

    file: str
    line: Optional[int]
    column: Optional[str]
    message: str

class FitError(ValueError):
    """A fit that cannot be made (too few points, no signal, an optimiser that failed)."""

    file: str
    sample: str
    model: str
    message: str

class ExportError(ValueError):
    """Some selected fits could not be exported; the others were.

    ``refused``: one text per refused fit, ``FILE: sample 'x', ggx to appleseed: reason`` (the
    file where the fits came from one); ``written``: the paths written (empty without
    ``out``); ``text``: without ``out``, the text of the exports that were made, else None.
    """

    refused: list[str]
    written: list[pathlib.Path]
    text: Optional[str]

class LongRunWarning(UserWarning):
    """A run of random walks estimated to take over ten seconds is about to start.

    Warned by ``fit``, ``report``, ``synth``, ``tables``, ``table_shard``, ``export`` and
    ``Microsurface.albedo``/``eval`` before their walks start, with the words of the command
    line's note: what will run, about how long it will take, what makes it shorter. Turned
    into an error (``warnings.simplefilter("error", stfit.LongRunWarning)``), it stops the call
    before its walks start.
    """

class _Ndf:
    def __eq__(self, other: object) -> bool:
        """Equal to an NDF of the same class with the same parameters."""
    def __hash__(self) -> int: ...
    @property
    def alpha(self) -> float:
        """The roughness alpha."""
    def d(self, wm: ArrayLike) -> FloatOrArray:
        """``D(wm)``, normalised by projected area (integral D(wm) wm.z dwm = 1); 0 for wm.z <= 0."""
    def lambda_(self, w: ArrayLike) -> FloatOrArray:
        """Smith ``Lambda(w)`` on the whole sphere, extended by Lambda(-w) = -1 - Lambda(w);
        ``inf`` on the horizon (z = 0), where it diverges (``g1`` is 0 there, ``sigma`` finite)."""
    def sigma(self, w: ArrayLike) -> FloatOrArray:
        """Projected area ``sigma(w) = integral max(0, w.wm) D(wm) dwm`` (= w.z (1 + Lambda(w)) above the horizon)."""
    def g1(self, w: ArrayLike) -> FloatOrArray:
        """Smith masking ``G1(w) = 1 / (1 + Lambda(w'))``, ``w'`` mirrored to the upper hemisphere."""
    def sample_visible(self, w: ArrayLike, seed: int = 0) -> npt.NDArray[np.float64]:
        """Exact visible normals: one facet normal per direction ``w`` (any direction on the
        sphere), drawn from ``D_w(wm) = max(0, w.wm) D(wm) / sigma(w)``. Unit vectors with
        ``wm.z > 0`` and ``w.wm > 0``, shape ``(..., 3)``; the same for a seed whatever the
        number of threads. A direction from which no visible normal can be drawn (``sigma(w) = 0``:
        straight below, or far below the horizon where the NDF's tail underflows) raises
        ValueError naming the row."""

class StudentT(_Ndf):
    """The Student-T NDF of d'Eon 2023 with roughness ``alpha`` > 0 and shape ``gamma`` > 3/2
    (GGX at gamma = 2, Beckmann as gamma grows)."""

    def __init__(self, alpha: float, gamma: float) -> None: ...
    @property
    def gamma(self) -> float:
        """The shape gamma."""

class Ggx(_Ndf):
    """The GGX (Trowbridge-Reitz) NDF with roughness ``alpha`` > 0."""

    def __init__(self, alpha: float) -> None: ...

class Beckmann(_Ndf):
    """The Beckmann NDF with roughness ``alpha`` > 0."""

    def __init__(self, alpha: float) -> None: ...

Ndf = Union[StudentT, Ggx, Beckmann]

class BsdfSamples:
    """Directions drawn by ``RoughDielectric.sample``: ``wo`` (unit vectors; zeros where no
    direction was drawn), ``weight = eval(wi, wo) / pdf``, ``pdf`` (solid-angle density) and
    ``valid`` (False where the draw failed: grazing ``wi`` or a direction that landed on the
    wrong side; then weight and pdf are 0)."""

    wo: npt.NDArray[np.float64]
    weight: FloatOrArray
    pdf: FloatOrArray
    valid: Union[bool, npt.NDArray[np.bool_]]

class RoughDielectric:
    """The single-scattering rough dielectric of Walter et al. 2007: index 1 above, ``eta``
    (> 0, != 1) below, exact unpolarised Fresnel, ``masking`` ``'separable'`` (G1 G1, as the
    published fits) or ``'correlated'`` (height-correlated Smith). Light may come from either
    side."""

    def __init__(self, ndf: Ndf, eta: float, masking: str = "separable") -> None: ...
    def __eq__(self, other: object) -> bool:
        """Equal when the NDFs, ``eta`` and ``masking`` are."""
    def __hash__(self) -> int: ...
    @property
    def ndf(self) -> Ndf: ...
    @property
    def eta(self) -> float: ...
    @property
    def masking(self) -> str: ...
    def eval(self, wi: ArrayLike, wo: ArrayLike) -> FloatOrArray:
        """``f(wi, wo) |wo.z|`` (reflection when wi and wo are on the same side, else
        transmission). ``wi`` and ``wo`` have the same shape, or one is a single direction."""
    def pdf(self, wi: ArrayLike, wo: ArrayLike) -> FloatOrArray:
        """The solid-angle density with which ``sample`` returns ``wo``."""
    def sample(self, wi: ArrayLike, seed: int = 0) -> BsdfSamples:
        """One outgoing direction per ``wi``: a visible normal from wi's side, then reflection
        with probability F, else refraction."""

class Albedo:
    """Fractions of the incident flux leaving on the light's side (``reflectance``) and the
    other (``transmittance``), with standard errors (None with fewer than 2 walks, where they
    are undefined, as ``stfit albedo --json`` gives null, and for a side that no walk
    reached, which has instead ``reflectance_upper_bound`` / ``transmittance_upper_bound``,
    the one-sided 95% bound ``1 - 0.05 ** (1 / walks)``, None for a reached side),
    ``mean_bounces`` (scattering
    events per walk that left within the orders: the path length, which facet albedos do not
    change, since they weight a walk rather than end it; None when no walk left within the
    orders, as ``stfit albedo --json`` gives null), the fraction
    ``truncated`` dropped at the safety cap, and ``walks``. Compares and hashes by value;
    pickles with every number exact."""

    reflectance: float
    transmittance: float
    reflectance_stderr: Optional[float]
    transmittance_stderr: Optional[float]
    reflectance_upper_bound: Optional[float]
    transmittance_upper_bound: Optional[float]
    mean_bounces: Optional[float]
    truncated: float
    walks: int
    def __eq__(self, other: object) -> bool:
        """Equal when every field is the same number (an undefined standard error equals
        itself)."""
    def __hash__(self) -> int: ...

class Microsurface:
    """The multiple-scattering dielectric microsurface: the height-field random walk of Heitz
    et al. 2016 on the Smith microsurface of ``ndf`` with smooth dielectric facets of index
    ``eta``, restricted to ``orders``: ``'single'`` (order 1), ``'multiple'`` (orders >= 2) or
    ``'all'``. Its masking is height-correlated by construction. A Student-T ``ndf`` needs
    gamma >= 1.501 (walk lengths diverge at 3/2): a smaller shape raises ``ValueError`` here."""

    def __init__(self, ndf: Ndf, eta: float, orders: str = "all") -> None: ...
    def __eq__(self, other: object) -> bool:
        """Equal when the NDFs, ``eta`` and ``orders`` are."""
    def __hash__(self) -> int: ...
    @property
    def ndf(self) -> Ndf: ...
    @property
    def eta(self) -> float: ...
    @property
    def orders(self) -> str: ...
    def albedo(self, wi: ArrayLike, walks: int = 1_000_000, seed: int = 1) -> Albedo:
        """The albedo for light from the single unit direction ``wi`` (shape (3,)), from
        ``walks`` walks (in [1, 1e9], else ValueError); parallel, identical for a seed whatever
        the number of threads. A ``wi`` on the horizon (z = 0; ``stfit albedo --theta-i 90``),
        from which no flux arrives, raises ValueError."""
    def eval(
        self, wi: ArrayLike, wo: ArrayLike, walks: int = 100_000, seed: int = 1
    ) -> tuple[FloatOrArray, FloatOrArray]:
        """Monte Carlo estimates of ``f(wi, wo) |wo.z|`` and their standard errors. Pairs that
        share a ``wi`` share one set of ``walks`` walks, seeded by the direction and ``seed``;
        with dielectric or conductor facets every pair adds a quarter as many walks from its
        ``wo``, toward ``wi``, weighted path by path against those from ``wi`` (bidirectional
        estimates). Each estimate depends on its pair and the seed only. ``walks`` is in
        [1, 1e9] (else ValueError); with 1 walk the standard errors are undefined and given as
        NaN (``stfit eval`` leaves them empty)."""

class Dataset:
    """Measurements: named samples of points (angles, value ``L`` or BSDF, weight). Equal
    when the source, the sample names and every point are; unhashable; pickles with every
    number exact (a task of a cluster can take one)."""

    def __eq__(self, other: object) -> bool: ...
    __hash__: None  # type: ignore[assignment]

    @property
    def source(self) -> str:
        """The file, the paths joined by ', ', '<arrays>', '<DataFrame>' or '<synth>'."""
    @property
    def samples(self) -> list[str]:
        """Sample names in order of first appearance ('' for a file without a sample column)."""
    @property
    def n_points(self) -> int: ...
    def sample(self, name: str) -> "Dataset":
        """The dataset restricted to one sample (LoadError if there is none of that name)."""
    def columns(self) -> dict[str, Any]:
        """The points as columns named as a file's header (in-plane: sample, theta_i_deg,
        theta_o_deg, L, weight; general: sample, theta_i_deg, phi_i_deg, theta_o_deg,
        phi_o_deg, bsdf, weight); ``pandas.DataFrame(d.columns())`` and ``stfit.load`` of it
        round-trip."""
    def __len__(self) -> int: ...

def load(source: DataSource, *, sample: Optional[str] = None) -> Dataset:
    """Reads measurements (data-format.md): a CSV file (in-plane or general) or pab-opto file, a
    folder of them, a list of paths, or in-memory columns named as a file's header (a mapping of
    names to arrays, or a pandas DataFrame), validated by the same rules: the names are strings,
    each column is 1-D (one value per row), the number columns (angles, ``L``, ``sqrt_L``,
    ``bsdf``, ``weight``) have an integer or float dtype (booleans, complex numbers and text are
    refused, not converted), a masked array with a masked element is refused at its row, and a
    missing sample name (None, NaN, pandas' NA) is refused as an empty one. Raises LoadError with the file (``<arrays>``, ``<DataFrame>`` for columns), line
    (row k is line k + 2) and column of the first problem."""

class FitResult:
    """One model fitted to one sample: every key of a record of the fits JSON
    (fits-format.md) is an attribute of the same name."""

    sample: str
    model: str
    alpha: float
    gamma: Optional[float]
    gamma_fixed: bool
    scale: float
    eta: float
    masking: str
    orders: str
    walks: Optional[int]
    seed: Optional[int]
    eta_fixed: bool
    scale_fixed: bool
    loss: str
    log_floor: Optional[float]
    optimizer: str
    multiple_term: Optional[str]
    measured: str
    rmse_sqrt_l: float
    n_points: int
    alpha_stderr: Optional[float]
    gamma_stderr: Optional[float]
    eta_stderr: Optional[float]
    scale_stderr: Optional[float]
    iterations: int
    data: Optional[str]
    warnings: list[dict[str, Any]]
    """Why the fit cannot be trusted as it stands (one dict per reason, with its ``kind``);
    empty for a sound fit. A fit with any warning has no standard errors."""
    stfit_version: str
    def label(self) -> str: ...
    def predict(self, theta_i_deg: Sequence[float], theta_o_deg: Sequence[float]) -> list[float]:
        """The fitted model's ``L`` at in-plane configurations (theta_i in [0, 90), theta_o in
        (90, 270), degrees, as in data-format.md); an angle outside them, NaN included, raises
        ValueError naming it."""
    def to_json(self) -> str:
        """The record as JSON text, exactly as in the fits file."""
    def to_dict(self) -> dict[str, Any]:
        """The record as a dict with the keys of the fits JSON."""
    @staticmethod
    def from_json(text: str) -> "FitResult": ...

def fit(
    data: DataSource,
    *,
    model: str = "student-t",
    gamma: Optional[float] = None,
    sample: Optional[str] = None,
    eta: Union[float, str, None] = None,
    scale: Union[float, str, None] = None,
    loss: str = "sqrt",
    log_floor: Optional[float] = None,
    optimizer: str = "nelder-mead",
    masking: Optional[str] = None,
    orders: str = "single",
    walks: Optional[int] = None,
    seed: Optional[int] = None,
    multiple_term: Optional[str] = None,
) -> list[FitResult]:
    """Fits ``model`` ('beckmann', 'ggx', 'student-t' or 'all': the four models Beckmann, GGX,
    Student-T with gamma = 3 and with gamma free) to every sample, with the command line's
    options and defaults: ``eta`` 1.51 (a number or 'free'), ``scale`` 'free' (or a number to
    hold it at, at least 2.2e-308; a bool for either raises ValueError), ``log_floor`` of ``loss`` 'log' in [1e-12, 1] (default
    1e-3), ``orders`` 'single' or 'all' (the random walk's orders >= 2 added, ``walks`` per
    incidence, in [2, 1e9], default 20,000, from ``seed``, default 1; ``multiple_term``
    'surrogate', the default, interpolates that term between a few walk sets while searching,
    'exact' walks at every evaluation), ``masking`` separable for single scattering. As on the
    command line, an option given where it does not apply raises ValueError rather than being
    ignored: ``walks``, ``seed`` and ``multiple_term`` apply to orders 'all' only, ``log_floor``
    to loss 'log' only. Raises ValueError for bad options, LoadError for bad data, FitError for
    a fit that cannot be made."""

def table(fits: Sequence[FitResult]) -> str:
    """The fits as the text table ``stfit DATA`` prints."""

def fits_json(fits: Sequence[FitResult]) -> str:
    """The fits as a fits file (what ``stfit DATA --json`` prints)."""

def read_fits(path: PathLike) -> list[FitResult]:
    """The fits of a stored fits file."""

def synth(
    model: str,
    alpha: float,
    gamma: Optional[float] = None,
    *,
    scale: float = 1.0,
    noise: float = 0.0,
    seed: int = 1,
    grid: str = "in-plane",
    theta_i: Union[Sequence[float], str, None] = None,
    phi_i: Union[Sequence[float], str, None] = None,
    theta_o: Union[Sequence[float], str, None] = None,
    phi_o: Union[Sequence[float], str, None] = None,
    eta: float = 1.51,
    masking: Optional[str] = None,
    orders: str = "single",
    walks: Optional[int] = None,
    sample: str = "synthetic",
    out: Optional[PathLike] = None,
) -> Dataset:
    """Synthetic measurements of known truth (``stfit synth``): the model on an angle grid
    ('in-plane': L, or 'general': the BSDF on both sides) with noise max(0, v (1 + noise z)),
    written as CSV to ``out`` when given. Angle lists are sequences or the command line's text
    ('0,30,60', '106:254:2'). ``walks`` (per incidence, default 20,000) applies to orders 'all'
    only; given with orders 'single' it raises ValueError."""

def report(
    data: DataSource,
    fits: Optional[Sequence[FitResult]] = None,
    *,
    out: PathLike,
    y_axis: str = "sqrt",
    eta: Union[float, str, None] = None,
    scale: Union[float, str, None] = None,
    loss: Optional[str] = None,
    log_floor: Optional[float] = None,
    optimizer: Optional[str] = None,
    masking: Optional[str] = None,
    orders: Optional[str] = None,
    walks: Optional[int] = None,
    seed: Optional[int] = None,
    multiple_term: Optional[str] = None,
) -> list[pathlib.Path]:
    """Writes the report of ``stfit report`` into ``out``: comparison figures (SVG, PNG) and
    fits.md. Without ``fits``, the four models are fitted first with the options given (as in
    ``fit``: loss "sqrt", log_floor 1e-3, optimizer "nelder-mead", orders "single", walks
    20,000, seed 1, multiple_term "surrogate" where not given; an option that does not apply,
    such as ``walks`` with orders "single", raises ValueError). With ``fits`` every fit option
    raises ValueError: stored fits carry their own; so does an empty ``fits``. Returns the
    paths written; non-fatal findings are issued as warnings."""

def export(
    fits: Union[FitResult, Sequence[FitResult], PathLike],
    to: str,
    *,
    sample: Optional[str] = None,
    model: Optional[str] = None,
    out: Optional[PathLike] = None,
    layer: Optional[str] = None,
    absorption: Optional[float] = None,
    walks: Optional[int] = None,
    seed: Optional[int] = None,
) -> Union[str, list[pathlib.Path]]:
    """Exports stored fits as ``stfit export`` does (the same code, texts byte for byte).

    ``fits``: a ``FitResult``, a sequence of them, or the path of a fits file. ``to``: the
    target, ``mitsuba3``, ``pbrt-v4``, ``cycles``, ``appleseed``, ``openpbr``, ``vray`` or
    ``radiance`` (LBNL WINDOW BSDF XML, Klems full basis). ``sample`` and ``model``
    (``beckmann``, ``ggx``, ``student-t``: gamma fitted, ``student-t-fixed``: gamma held)
    select fits. Without ``out``, returns the text ``stfit export`` prints. With ``out`` a
    file, writes one file of each type (several fits go into it; the first type at ``out``,
    the others beside it with their own extension, such as Mitsuba's ``.xml`` and ``.py``);
    with ``out`` an existing folder, one file per fit named ``SAMPLE_MODEL-TARGET.EXT``; then
    returns the paths written. Radiance writes one file per fit, so several fits need a folder.

    Radiance options: ``layer`` ``pane`` (the default: the rough face over a smooth back face,
    with all inter-reflections) or ``interface`` (the single rough interface); ``absorption``:
    the fraction absorbed in one normal crossing of the pane, in [0, 1), default 0; ``walks``:
    random walks per Klems patch where walks are needed, at least 2, rounded up to a square,
    default 65,536; ``seed``: their seed, default 1. Given with another target they raise
    ``ValueError``, and so do ``walks`` and ``seed`` where nothing walks (the interface of
    single-scattering fits), as on the command line. Clamps and other departures from the fit are issued as warnings; a bad option or
    fit raises ``ValueError``, an unreadable file ``OSError``. A fit whose export the target
    refuses (appleseed's ior range, say) does not stop the others: they are written, then
    ``ExportError`` is raised with ``refused``, ``written`` and ``text``."""

AxisLike = Union[str, Sequence[float]]

def tables(
    ndf: str,
    *,
    alpha_grid: Optional[AxisLike] = None,
    gamma_grid: Optional[AxisLike] = None,
    mu_grid: Optional[AxisLike] = None,
    eta_grid: Optional[AxisLike] = None,
    side: Optional[str] = None,
    surface: str = "dielectric",
    n: Optional[float] = None,
    k: Optional[float] = None,
    orders: str = "single",
    masking: str = "correlated",
    layout: Optional[str] = None,
    format: Optional[str] = None,
    shard: Optional[str] = None,
    walks: Optional[int] = None,
    seed: Optional[int] = None,
    out: Optional[PathLike] = None,
) -> Union[Table, str]:
    """Computes a directional-albedo (energy-compensation) table as ``stfit tables`` does:
    the same options, defaults and checks, the same bytes (tables-format.md), with the GIL
    released, on all cores.

    ``ndf``: ``beckmann``, ``ggx`` or ``student-t``. Axes (``alpha_grid``: alpha in [1e-8, 4];
    ``gamma_grid``: Student-T only, gamma in [1.6, 40]; ``mu_grid``: the cosine of incidence in
    [1e-4, 1]; ``eta_grid``: dielectrics only, n_inside / n_outside in (1, 100]): the text of
    the command line, ``"START:END:COUNT"``, ``"MAP:START:END:COUNT"`` (MAP ``lin``, ``log``,
    ``sq``: alpha = x^2, ``cycles-ior`` for eta) or ``"v1,v2,..."``, or a sequence of values.
    ``side``: ``outside``, ``inside`` or ``both`` (default for dielectrics; conductors:
    outside only). ``surface``: ``dielectric`` or ``conductor`` (Fresnel with ``n`` and ``k``
    together, else mirror facets). ``orders``: ``single`` (E_ss by quadrature), ``multiple``
    (also orders >= 2 by random walks) or ``all`` (also E_all). ``masking`` of E_ss:
    ``correlated``, ``reflection-form`` or ``separable``. ``layout="cycles"``: Blender Cycles'
    nodes instead of the alpha, mu and eta axes. ``walks`` (default 100000) and ``seed``
    (default 1): orders multiple or all only.

    Returns the ``Table``; with ``shard="K/N"`` the shard file's JSON text instead (for
    ``merge_table_shards``). With ``out``, also writes the file ``stfit tables --out`` writes:
    in ``format`` (``csv``, ``npy`` or ``c``; not with ``shard``), by default from the
    extension of ``out`` (``.npy``; ``.h``, ``.hpp``, ``.c``, ``.inc`` for C; else CSV). Bad
    options raise ``ValueError`` (``TypeError`` for an axis of the wrong type), a file that
    cannot be written ``OSError``; walks that reached the safety cap on scattering events are
    a warning."""

def table_spec(
    ndf: str,
    *,
    alpha_grid: Optional[AxisLike] = None,
    gamma_grid: Optional[AxisLike] = None,
    mu_grid: Optional[AxisLike] = None,
    eta_grid: Optional[AxisLike] = None,
    side: Optional[str] = None,
    surface: str = "dielectric",
    n: Optional[float] = None,
    k: Optional[float] = None,
    orders: str = "single",
    masking: str = "correlated",
    layout: Optional[str] = None,
    walks: Optional[int] = None,
    seed: Optional[int] = None,
) -> str:
    """The JSON text of the table specification the options of ``tables`` describe (checked
    as ``tables`` checks them), for ``table_shard``: one task of a cluster computes one shard,
    ``merge_table_shards`` joins them into the table ``tables`` computes."""

def table_shard(spec: str, index: int = 1, count: int = 1) -> str:
    """Computes shard ``index`` of ``count`` of a directional-albedo (energy) table, ``spec``
    being the JSON text of a table specification (the ``spec`` of a shard file of
    ``stfit tables --shard K/N``, tables-format.md); returns the shard file's JSON text. One
    task of a cluster computes one shard."""

class Table:
    """A whole directional-albedo table, in the formats of ``stfit tables --format``."""

    def spec(self) -> str:
        """The specification as JSON text."""
    def npy(self) -> bytes:
        """The .npy bytes: a structured array of shape (sides, gamma, eta, mu, alpha)."""
    def csv(self) -> str: ...
    def c_header(self) -> str:
        """The C header in Cycles' layout."""
    def write(self, out: PathLike, format: Optional[str] = None) -> None:
        """Writes the table as ``stfit tables merge --out`` does: in ``format`` (``csv``,
        ``npy`` or ``c``), by default from the extension of ``out``."""

def merge_table_shards(shards: Sequence[str]) -> Table:
    """Joins shard texts (every shard 1..N of one specification exactly once) into the table
    one run computes (``stfit tables merge``)."""
