//! Reading and validating measurement files (the format of `data-format.md`).
//!
//! Every problem is a [`LoadError`] that names the file, and where they apply the line and the
//! column, so that a user can go straight to the bad field.

use std::borrow::Cow;
use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};

use stfit_core::error::show;
use thiserror::Error;

use crate::conventions::{
    THETA_I_RANGE, THETA_O_RANGE, THETA_RANGE, theta_i_in_range, theta_in_range, theta_o_in_range,
};
use crate::data::{Dataset, Measurement, Sample};
use crate::files::FileId;

/// Name of the optional column holding the sample name.
pub const COL_SAMPLE: &str = "sample";
/// Name of the incidence-angle column (degrees: in [0, 90) from the outside in an in-plane
/// file, the polar angle of the direction toward the light in a general file).
pub const COL_THETA_I: &str = "theta_i_deg";
/// Name of the outgoing-direction column (degrees: the transmitted direction inside the glass
/// in (90, 270) in an in-plane file, the polar angle toward the detector in a general file).
pub const COL_THETA_O: &str = "theta_o_deg";
/// Name of the value column holding `L`.
pub const COL_L: &str = "L";
/// Name of the value column holding `sqrt(L)`.
pub const COL_SQRT_L: &str = "sqrt_L";
/// Name of a general file's azimuth of the direction toward the light (degrees).
pub const COL_PHI_I: &str = "phi_i_deg";
/// Name of a general file's azimuth of the direction toward the detector (degrees).
pub const COL_PHI_O: &str = "phi_o_deg";
/// Name of a general file's value column, the BSDF in 1/sr.
pub const COL_BSDF: &str = "bsdf";
/// Name of the optional least-squares weight column.
pub const COL_WEIGHT: &str = "weight";

/// The byte-order mark a UTF-8 file may start with; it is skipped.
const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// A measurement file that could not be read, with where the problem is.
///
/// Displays as `<file>:<line>: column '<col>': <what>`, leaving out the line or the column when
/// the problem has none (a missing file has neither).
#[derive(Debug, Clone, PartialEq, Error)]
pub struct LoadError {
    /// The file being read.
    pub file: PathBuf,
    /// 1-based line of the file, when the problem is on one line.
    pub line: Option<u64>,
    /// The column's header name (or a description of it), when the problem is in one column.
    pub column: Option<String>,
    /// What is wrong.
    pub kind: LoadErrorKind,
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        if let Some(column) = &self.column {
            // A header name from the file, shown as every text of a file is.
            write!(f, ": column '{}'", crate::data::short(column))?;
        }
        write!(f, ": {}", self.kind)
    }
}

/// What is wrong with a measurement file.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LoadErrorKind {
    /// The file could not be opened or read.
    #[error("cannot read the file: {0}")]
    Io(String),
    /// No header: the file is empty or holds only blank and comment lines; `expected` is a
    /// header line of the kind of table being read.
    #[error("the file is empty; expected a header line such as '{expected}' (see data-format.md)")]
    Empty { expected: &'static str },
    /// A header but no measurement rows.
    #[error("no measurements after the header")]
    NoRows,
    /// A required column is not in the header.
    #[error("missing from the header (the header has: {found})")]
    MissingColumn { found: String },
    /// Neither `L` nor `sqrt_L` is in the header.
    #[error(
        "missing: exactly one value column 'L' or 'sqrt_L' is needed (the header has: {found})"
    )]
    MissingValueColumn { found: String },
    /// A value column of the other file form: `bsdf` in an in-plane file, `L` or `sqrt_L` in a
    /// general one.
    #[error("{}", if *general {
        "a general file (with phi_i_deg and phi_o_deg) gives the BSDF in a column 'bsdf', not L or sqrt_L"
    } else {
        "'bsdf' is the value column of general files, which have phi_i_deg and phi_o_deg"
    })]
    ValueOfOtherForm { general: bool },
    /// An optional column, or one that makes a file general, is not in the header, but a
    /// name that differs from it only in case is (field `field`, 1-based): read as an
    /// unrecognised column it would change the data silently (every sample merged into one,
    /// every weight 1, or a general file read as in-plane).
    #[error(
        "not in the header, but field {field} is '{}': column names are case-sensitive, so \
         rename it (or give it another name to have it ignored)",
        crate::data::short(found)
    )]
    CaseVariantColumn { found: String, field: usize },
    /// Both `L` and `sqrt_L` are in the header.
    #[error("'L' and 'sqrt_L' are both present; give exactly one value column")]
    BothValueColumns,
    /// A recognised column name appears twice in the header.
    #[error("appears twice in the header (fields {first} and {second})")]
    DuplicateColumn { first: usize, second: usize },
    /// A field holds bytes that are not UTF-8.
    #[error("bytes that are not valid UTF-8")]
    NotUtf8,
    /// A numeric field is empty.
    #[error("empty value, expected a number")]
    EmptyValue,
    /// A numeric field does not parse as a number.
    #[error("'{}' is not a number", crate::data::short(.0))]
    NotANumber(String),
    /// A numeric field is NaN or infinite.
    #[error("'{}' is not a finite number", crate::data::short(.0))]
    NonFinite(String),
    /// A nonzero numeric field too small in magnitude for a double (at most 2^-1075, about
    /// 2.47e-324, half the smallest subnormal): it would read as 0.
    #[error(
        "'{}' is not 0 but too small to be represented (magnitude at most about 2.47e-324): it would read as 0",
        crate::data::short(.0)
    )]
    Unrepresentable(String),
    /// A nonzero value whose derived quantity underflows to 0: `L` of a `sqrt_L`.
    #[error("{value:e} is too small: {derived} underflows to 0")]
    Underflow { value: f64, derived: &'static str },
    /// A value, `sqrt(L)` or weight field is negative.
    #[error("{} is negative; must be >= 0", show(*.0))]
    Negative(f64),
    /// A finite value whose derived quantity is not: `L` of a `sqrt_L`, or the BSDF of a
    /// pab-opto DSF.
    #[error("{value:e} is too large: {derived} overflows to infinity")]
    Overflow { value: f64, derived: &'static str },
    /// An angle outside its range.
    #[error("{} is out of range; must be in {range}", show(*.value))]
    AngleOutOfRange { value: f64, range: &'static str },
    /// A row with fewer fields than the header.
    #[error("missing: the row has {found} fields, the header {expected}")]
    ShortRow { found: usize, expected: usize },
    /// A row with more fields than the header.
    #[error("the row has {found} fields but the header only {expected} (an unquoted comma?)")]
    LongRow { found: usize, expected: usize },
    /// An empty field in the `sample` column.
    #[error("empty sample name")]
    EmptySampleName,
    /// Every weight of a sample is zero, so nothing constrains its fit.
    #[error(
        "every weight of sample '{}' is 0; at least one must be positive",
        crate::data::short(.0)
    )]
    AllWeightsZero(String),
    /// A requested sample name is not in the file.
    #[error(
        "no sample named '{}' (the file has: {})",
        crate::data::short(name),
        crate::data::short(available)
    )]
    UnknownSample { name: String, available: String },
    /// A sample was requested from a file without a `sample` column.
    #[error(
        "the file has no 'sample' column, so no sample named '{}' can be selected",
        crate::data::short(.0)
    )]
    NoSampleColumn(String),
    /// A pab-opto header line after the first data line.
    #[error("a header line after the data; every '#' line must come first")]
    HeaderAfterData,
    /// A pab-opto header line whose key an earlier line already gave.
    #[error("given again; line {first} gave it already, and each header line may appear once")]
    RepeatedHeader { first: u64 },
    /// A pab-opto incident angle that two header lines give differently (`#intheta` and
    /// `#incident_angle`): `other` is the earlier line's key and angle, e.g. `#intheta 60`.
    #[error("disagrees with '{other}' on line {other_line}")]
    IncidenceConflict { other: String, other_line: u64 },
    /// A pab-opto sample name without its double quotes.
    #[error("the sample name must be in double quotes")]
    Unquoted,
    /// A pab-opto format or colorimetry this reader does not know.
    #[error(
        "'{0}' is not a known format (expected 'theta phi DSF' or 'theta phi BSDF', colorimetry CIE-Y or CIE-XYZ)"
    )]
    UnknownFormat(String),
    /// A line with another number of fields than its format has.
    #[error("{found} fields, expected {expected}")]
    Fields { expected: usize, found: usize },
    /// A pab-opto file without a `#format:` line.
    #[error("missing: no '#format: theta phi DSF' (or BSDF) header line")]
    NoFormat,
    /// A pab-opto file without its incident direction.
    #[error("missing: no '#intheta' and '#inphi' (or '#incident_angle') header lines")]
    NoIncidence,
    /// A pab-opto file with scattered directions on both sides of the surface.
    #[error(
        "on the other side of the surface from the file's first direction; a file holds one scattered hemisphere"
    )]
    BothSides,
    /// A folder with nothing to read.
    #[error("the folder holds no measurement files")]
    EmptyFolder,
    /// A file named twice among the paths to read (directly or inside a folder given too):
    /// its measurements would count twice and shrink every standard error.
    #[error("the file is given twice (also as {0}); its measurements would count twice")]
    Repeated(String),
    /// A column that the command writes is already in its input.
    #[error("is written by stfit; the input must not have it")]
    Reserved,
    /// A direction that the library does not take (not a unit vector, or a subnormal `z`).
    #[error("{0}")]
    Direction(crate::pairs::DirectionProblem),
    /// The CSV structure itself is broken.
    #[error("malformed CSV: {0}")]
    Csv(String),
    /// Text after the closing quote of a quoted field (RFC 4180 allows none; only the
    /// whitespace trimmed around every field may follow it).
    #[error("text after the closing quote of a quoted field (a quote inside one is written twice)")]
    TextAfterQuote,
    /// A quoted field whose closing quote never comes.
    #[error("a quoted field is not closed before the end of the file")]
    UnterminatedQuote,
    /// An in-memory column whose length differs from the first column's.
    #[error("has {found} rows, the first column {expected}")]
    ColumnLength { found: usize, expected: usize },
}

impl LoadError {
    fn new(file: &Path, line: Option<u64>, column: Option<&str>, kind: LoadErrorKind) -> Self {
        Self {
            file: file.to_path_buf(),
            line,
            column: column.map(str::to_owned),
            kind,
        }
    }

    /// The error of an I/O failure on the file or folder at `path`.
    fn io(path: &Path, e: std::io::Error) -> Self {
        Self::new(path, None, None, LoadErrorKind::Io(e.to_string()))
    }
}

/// Reads and validates the measurement file at `path`: a CSV file (`data-format.md`, in-plane
/// or general) or a pab-opto file ([`crate::pabopto`]), told apart by their contents; a
/// folder is read as [`load_paths`] reads one.
pub fn load_path(path: &Path) -> Result<Dataset, LoadError> {
    load_paths(&[path.to_path_buf()])
}

/// Reads several measurement files and folders into one dataset: every file of a folder (in
/// name order, hidden files left out), each a CSV or a pab-opto file, samples merged by name in
/// order of first appearance. The dataset's source is the one path given, or the paths joined
/// by `, `.
pub fn load_paths(paths: &[PathBuf]) -> Result<Dataset, LoadError> {
    let files = data_files(paths)?;
    // The first path of each file read: a folder of many files is checked in linear time.
    let mut seen: HashMap<FileId, &PathBuf> = HashMap::new();
    for file in &files {
        let Some(id) = FileId::of(file) else {
            continue;
        };
        if let Some(first) = seen.get(&id) {
            let first = first.display().to_string();
            return Err(LoadError::new(
                file,
                None,
                None,
                LoadErrorKind::Repeated(first),
            ));
        }
        seen.insert(id, file);
    }
    // Each sample with the file and line of its first row, to place a sample-wide error.
    let mut samples: Vec<(Sample, &Path, Option<u64>)> = Vec::new();
    // Where each sample name is in `samples`: a file of many samples merges in linear time.
    let mut index: HashMap<String, usize> = HashMap::new();
    for file in &files {
        let bytes = crate::files::read_input(file).map_err(|e| LoadError::io(file, e))?;
        let parts = if crate::pabopto::is_pabopto(&bytes) {
            let (name, points) = crate::pabopto::read_pabopto(file, &bytes)?;
            vec![(Sample { name, points }, None)]
        } else {
            let (records, quote_problem) = records_until_quote_problem(file, &bytes)?;
            samples_from_records(file, records, quote_problem)?
                .into_iter()
                .map(|(sample, line)| (sample, Some(line)))
                .collect()
        };
        for (part, line) in parts {
            match index.get(&part.name) {
                Some(&i) => samples[i].0.points.extend(part.points),
                None => {
                    index.insert(part.name.clone(), samples.len());
                    samples.push((part, file, line));
                }
            }
        }
    }
    // A sample's weights are checked once its points of every file are merged.
    check_weights(samples.iter().map(|(s, file, line)| (s, *file, *line)))?;
    let samples = samples.into_iter().map(|(s, ..)| s).collect();
    let source = match paths {
        [one] => one.clone(),
        many => PathBuf::from(
            many.iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", "),
        ),
    };
    Ok(Dataset { source, samples })
}

/// The files that [`load_paths`] reads for `paths`: each path that is not a folder, and for a
/// folder every file in it, in name order, hidden files (names starting with `.`) left out,
/// sub-folders not descended into. An empty folder, or one that cannot be listed, is an error.
pub fn data_files(paths: &[PathBuf]) -> Result<Vec<PathBuf>, LoadError> {
    let mut files = Vec::new();
    for path in paths {
        if path.is_dir() {
            let mut inside: Vec<PathBuf> = std::fs::read_dir(path)
                .map_err(|e| LoadError::io(path, e))?
                .filter_map(Result::ok)
                .map(|e| e.path())
                .filter(|p| {
                    p.is_file()
                        && !p
                            .file_name()
                            .is_some_and(|n| n.to_string_lossy().starts_with('.'))
                })
                .collect();
            if inside.is_empty() {
                return Err(LoadError::new(path, None, None, LoadErrorKind::EmptyFolder));
            }
            inside.sort();
            files.extend(inside);
        } else {
            files.push(path.clone());
        }
    }
    Ok(files)
}

/// Parses and validates measurement-file contents; `source` names them in errors.
pub fn load_bytes(source: &Path, bytes: &[u8]) -> Result<Dataset, LoadError> {
    let (records, quote_problem) = records_until_quote_problem(source, bytes)?;
    dataset_from_records(source, records, quote_problem)
}

/// One column of an in-memory table of measurements (see [`load_columns`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Column {
    /// Numbers (angles, values, weights).
    Numbers(Vec<f64>),
    /// Text (sample names, or anything else a file may carry).
    Text(Vec<String>),
}

impl Column {
    fn len(&self) -> usize {
        match self {
            Self::Numbers(v) => v.len(),
            Self::Text(v) => v.len(),
        }
    }

    /// Row `k` as the text of a file's field: numbers in Rust's shortest form that reads back
    /// to the same `f64` (NaN and infinities as `NaN`, `inf`, which the loader refuses).
    fn field(&self, k: usize) -> String {
        match self {
            Self::Numbers(v) => v[k].to_string(),
            Self::Text(v) => v[k].clone(),
        }
    }
}

/// Reads and validates an in-memory table of measurements whose columns are named as a
/// measurement file's header (`data-format.md`: in-plane or general, with the optional
/// `sample` and `weight` columns): every row is checked exactly as a file's row would be, and
/// a problem is reported as if the table were a CSV file named `source` with its header on
/// line 1, so row `k` (0-based) is line `k + 2`. Every column must have the same length.
pub fn load_columns(source: &Path, columns: &[(String, Column)]) -> Result<Dataset, LoadError> {
    let rows = columns.first().map_or(0, |(_, c)| c.len());
    if let Some((name, c)) = columns.iter().find(|(_, c)| c.len() != rows) {
        return Err(LoadError::new(
            source,
            None,
            Some(name),
            LoadErrorKind::ColumnLength {
                found: c.len(),
                expected: rows,
            },
        ));
    }
    let header: csv::ByteRecord = columns.iter().map(|(name, _)| name.as_str()).collect();
    let mut records = vec![(1, header)];
    for k in 0..rows {
        let record: csv::ByteRecord = columns.iter().map(|(_, c)| c.field(k)).collect();
        records.push((k as u64 + 2, record));
    }
    dataset_from_records(source, records, None)
}

/// Validates a header record and data records, each with its 1-based line, into a dataset;
/// `pending` is the problem of the row after the last record, reported once those are read.
fn dataset_from_records(
    source: &Path,
    records: Vec<(u64, csv::ByteRecord)>,
    pending: Option<LoadError>,
) -> Result<Dataset, LoadError> {
    let samples = samples_from_records(source, records, pending)?;
    check_weights(samples.iter().map(|(s, line)| (s, source, Some(*line))))?;
    Ok(Dataset {
        source: source.to_path_buf(),
        samples: samples.into_iter().map(|(s, _)| s).collect(),
    })
}

/// Refuses a sample whose every weight is 0, placed at its `file` and the `line` of its
/// first row.
fn check_weights<'a>(
    samples: impl IntoIterator<Item = (&'a Sample, &'a Path, Option<u64>)>,
) -> Result<(), LoadError> {
    for (sample, file, line) in samples {
        if sample.points.iter().all(|p| p.weight == 0.0) {
            return Err(LoadError::new(
                file,
                line,
                Some(COL_WEIGHT),
                LoadErrorKind::AllWeightsZero(sample.name.clone()),
            ));
        }
    }
    Ok(())
}

/// The samples of a header record and data records (as [`dataset_from_records`] reads them,
/// weights not yet checked), each with the line of its first row.
fn samples_from_records(
    source: &Path,
    records: Vec<(u64, csv::ByteRecord)>,
    pending: Option<LoadError>,
) -> Result<Vec<(Sample, u64)>, LoadError> {
    let mut records = records.into_iter();
    let Some((header_line, header_record)) = records.next() else {
        return Err(pending.unwrap_or_else(|| {
            LoadError::new(
                source,
                Some(1),
                None,
                LoadErrorKind::Empty {
                    expected: "sample,theta_i_deg,theta_o_deg,sqrt_L",
                },
            )
        }));
    };
    let header = Header::parse(source, header_line, &header_record)?;

    let mut samples: Vec<Sample> = Vec::new();
    let mut index: HashMap<String, usize> = HashMap::new();
    // Line of each sample's first row, to place a sample-wide error.
    let mut first_line: Vec<u64> = Vec::new();
    // The sample of the previous row: rows of one sample usually follow each other, so most
    // rows need neither a lookup nor a copy of their name.
    let mut last: Option<usize> = None;
    for (line, record) in records {
        let (name, point) = header.row(source, line, &record)?;
        let slot = match last.filter(|&i| samples[i].name == name) {
            Some(i) => i,
            None => match index.get(name) {
                Some(&i) => i,
                None => {
                    index.insert(name.to_owned(), samples.len());
                    samples.push(Sample {
                        name: name.to_owned(),
                        points: Vec::new(),
                    });
                    first_line.push(line);
                    samples.len() - 1
                }
            },
        };
        last = Some(slot);
        samples[slot].points.push(point);
    }
    if let Some(problem) = pending {
        return Err(problem);
    }
    if samples.is_empty() {
        return Err(LoadError::new(
            source,
            Some(header_line),
            None,
            LoadErrorKind::NoRows,
        ));
    }
    Ok(samples.into_iter().zip(first_line).collect())
}

/// The records of a CSV text as every stfit file is read (the text rules of
/// `data-format.md`), each with its 1-based line: a UTF-8 byte-order mark skipped, comment
/// lines (first byte `#`) and blank lines skipped, RFC 4180 quoting. The first record is the
/// header.
pub(crate) fn read_records(
    source: &Path,
    bytes: &[u8],
) -> Result<Vec<(u64, csv::ByteRecord)>, LoadError> {
    match records_until_quote_problem(source, bytes)? {
        (_, Some(problem)) => Err(problem),
        (records, None) => Ok(records),
    }
}

/// Records of a CSV text, each with its 1-based line.
pub(crate) type Records = Vec<(u64, csv::ByteRecord)>;

/// The records of [`read_records`] before the first row whose quoting RFC 4180 does not
/// allow, and the error for that row, so that problems of earlier rows can be reported first.
pub(crate) fn records_until_quote_problem(
    source: &Path,
    bytes: &[u8],
) -> Result<(Records, Option<LoadError>), LoadError> {
    let (bytes, problem) = strip_comments(bytes.strip_prefix(UTF8_BOM).unwrap_or(bytes));
    // Only `\n` ends a line (`\r\n` too, its `\r` trimmed with the field's whitespace): a
    // lone `\r` is not a line end.
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .terminator(csv::Terminator::Any(b'\n'))
        .from_reader(&*bytes);
    let mut lines = LineCounter::new(&bytes);
    let mut out = Vec::new();
    for record in reader.byte_records() {
        let record = record.map_err(|e| {
            let line = e.position().map(csv::Position::line);
            LoadError::new(source, line, None, LoadErrorKind::Csv(e.to_string()))
        })?;
        let line = lines.line_of(&record);
        if problem.as_ref().is_some_and(|p| line >= p.line) {
            break;
        }
        // A blank line, not one holding a quoted field (`""`).
        if is_blank(&record) && bytes.get(lines.offset) != Some(&b'"') {
            continue;
        }
        out.push((line, record));
    }
    let problem = problem.map(|p| p.error(source, out.first().map(|(_, header)| header)));
    Ok((out, problem))
}

/// A quoted field that RFC 4180 does not allow, on the row starting at `line`, in its field
/// `field` (0-based).
struct QuoteProblem {
    line: u64,
    field: usize,
    kind: LoadErrorKind,
}

impl QuoteProblem {
    /// The error, the field named by `header` (the file's header record, `None` when the
    /// problem is in the header itself).
    fn error(self, source: &Path, header: Option<&csv::ByteRecord>) -> LoadError {
        let column = match header {
            None => format!("header field {}", self.field + 1),
            Some(h) => h.get(self.field).map_or_else(
                || format!("extra field {}", self.field + 1),
                |name| trim_field(&String::from_utf8_lossy(name)).to_owned(),
            ),
        };
        LoadError::new(source, Some(self.line), Some(&column), self.kind)
    }
}

/// The trimmed UTF-8 fields of a record; a field that is not UTF-8 is an error naming its
/// column, `column(i)` for field `i`.
pub(crate) fn text_fields<'r>(
    source: &Path,
    line: u64,
    record: &'r csv::ByteRecord,
    column: impl Fn(usize) -> String,
) -> Result<Vec<&'r str>, LoadError> {
    record
        .iter()
        .enumerate()
        .map(|(i, field)| {
            std::str::from_utf8(field).map(trim_field).map_err(|_| {
                LoadError::new(source, Some(line), Some(&column(i)), LoadErrorKind::NotUtf8)
            })
        })
        .collect()
}

/// A CSV header: the line it is on and its fields.
pub type CsvHeader = (u64, Vec<String>);

/// The bytes of the CSV file at `path` ([`crate::files::read_input`]) and its header (its
/// first record, as the loader reads it), or `None` for a file with none.
pub fn read_header(path: &Path) -> Result<(Vec<u8>, Option<CsvHeader>), LoadError> {
    let bytes = crate::files::read_input(path).map_err(|e| LoadError::io(path, e))?;
    let header = header_of(path, &bytes)?;
    Ok((bytes, header))
}

/// The header of the CSV text `bytes` read from `path` ([`read_header`]).
fn header_of(path: &Path, bytes: &[u8]) -> Result<Option<CsvHeader>, LoadError> {
    let Some((line, record)) = read_records(path, bytes)?.into_iter().next() else {
        return Ok(None);
    };
    let fields = text_fields(path, line, &record, |i| format!("header field {}", i + 1))?;
    Ok(Some((
        line,
        fields.into_iter().map(str::to_owned).collect(),
    )))
}

/// The column of header field `i` (0-based) as messages name it: its header name, or for an
/// empty one (an unrecognised column, which may still be short of a field or not UTF-8) its
/// position, `field 3 (empty name)`, which `column ''` did not give.
fn column_label(names: &[String], i: usize) -> String {
    match names.get(i) {
        Some(name) if !name.is_empty() => name.clone(),
        _ => format!("field {} (empty name)", i + 1),
    }
}

/// A header's names as messages list them: each as [`crate::data::short`] shows text (control
/// characters escaped, long names cut), at most 20 of them. A file whose line ends are lone
/// `\r`s is one header line of every field, and a name may hold any text.
pub(crate) fn header_list(names: &[String]) -> String {
    const MAX: usize = 20;
    let mut list: Vec<String> = names
        .iter()
        .take(MAX)
        .map(|n| {
            if n.is_empty() {
                "(empty)".to_owned()
            } else {
                crate::data::short(n)
            }
        })
        .collect();
    if names.len() > MAX {
        list.push(format!("... ({} fields)", names.len()));
    }
    list.join(", ")
}

/// A record that is one whitespace-only field: an empty or blank line.
fn is_blank(record: &csv::ByteRecord) -> bool {
    record.len() == 1 && record[0].iter().all(|b| FIELD_SPACE.contains(b))
}

/// What is removed around every field and header name (`data-format.md`): spaces and tabs,
/// and the `\r` of a `\r\n` line end. Other whitespace (a no-break space) is part of the field.
const FIELD_SPACE: [u8; 3] = [b' ', b'\t', b'\r'];

/// `field` without the [`FIELD_SPACE`] around it. The bytes removed are ASCII, so the ends
/// kept are character boundaries.
fn trim_field(field: &str) -> &str {
    let bytes = field.as_bytes();
    let start = bytes
        .iter()
        .position(|b| !FIELD_SPACE.contains(b))
        .unwrap_or(bytes.len());
    let end = bytes
        .iter()
        .rposition(|b| !FIELD_SPACE.contains(b))
        .map_or(start, |i| i + 1);
    &field[start..end]
}

/// Converts the positions of records, met in file order, to 1-based line numbers.
///
/// The CSV reader's own position of a record is where it started scanning for it, before the
/// empty lines (`\n` only) it skips, so the record's first byte is found by skipping `\n`s from
/// there.
struct LineCounter<'a> {
    bytes: &'a [u8],
    offset: usize,
    line: u64,
}

impl<'a> LineCounter<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        Self {
            bytes,
            offset: 0,
            line: 1,
        }
    }

    /// The line on which `record` starts.
    fn line_of(&mut self, record: &csv::ByteRecord) -> u64 {
        let scan_start = record
            .position()
            .map_or(self.offset, |p| {
                usize::try_from(p.byte()).unwrap_or(usize::MAX)
            })
            .clamp(self.offset, self.bytes.len());
        let start = scan_start
            + self.bytes[scan_start..]
                .iter()
                .take_while(|&&b| b == b'\n')
                .count();
        let newlines = self.bytes[self.offset..start]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        self.line += newlines as u64;
        self.offset = start;
        self.line
    }
}

/// Empties every comment line (a line whose first byte is `#`, outside a quoted field),
/// keeping its line break so that the CSV reader's line numbers stay those of the file, and
/// finds the first quoted field that RFC 4180 does not allow: text after its closing quote
/// (whitespace aside), or no closing quote. The bytes end at that problem. A text with
/// neither `#` nor `"` has no comment and no quoted field: it is returned as it is, uncopied.
fn strip_comments(bytes: &[u8]) -> (Cow<'_, [u8]>, Option<QuoteProblem>) {
    if !bytes.iter().any(|&b| b == b'#' || b == b'"') {
        return (Cow::Borrowed(bytes), None);
    }
    #[derive(Clone, Copy)]
    enum State {
        LineStart,
        FieldStart,
        Unquoted,
        Quoted,
        QuoteInQuoted,
        AfterQuoted,
        Comment,
    }
    let mut out = Vec::with_capacity(bytes.len());
    let mut state = State::LineStart;
    // The current line, and the line and field of the row being read.
    let (mut line, mut row_line, mut field) = (1u64, 1u64, 0usize);
    for &b in bytes {
        if matches!(state, State::LineStart) && b != b'#' {
            (row_line, field) = (line, 0);
        }
        if b == b'\n' {
            line += 1;
        }
        state = match (state, b) {
            (State::Comment, b'\n') => State::LineStart,
            (State::Comment, _) => continue,
            (State::LineStart, b'#') => {
                state = State::Comment;
                continue;
            }
            (State::Quoted, b'"') => State::QuoteInQuoted,
            (State::Quoted, _) => State::Quoted,
            (State::QuoteInQuoted, b'"') => State::Quoted,
            (State::QuoteInQuoted | State::AfterQuoted, b' ' | b'\t' | b'\r') => State::AfterQuoted,
            (_, b'\n') => State::LineStart,
            (_, b',') => {
                field += 1;
                State::FieldStart
            }
            (State::QuoteInQuoted | State::AfterQuoted, _) => {
                let kind = LoadErrorKind::TextAfterQuote;
                return (
                    Cow::Owned(out),
                    Some(QuoteProblem {
                        line: row_line,
                        field,
                        kind,
                    }),
                );
            }
            (State::LineStart | State::FieldStart, b'"') => State::Quoted,
            _ => State::Unquoted,
        };
        out.push(b);
    }
    let problem = matches!(state, State::Quoted).then_some(QuoteProblem {
        line: row_line,
        field,
        kind: LoadErrorKind::UnterminatedQuote,
    });
    (Cow::Owned(out), problem)
}

/// Which value column the file gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ValueColumn {
    L,
    SqrtL,
    Bsdf,
}

/// What a recognised column holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    Sample,
    ThetaI,
    PhiI,
    ThetaO,
    PhiO,
    Value(ValueColumn),
    Weight,
}

/// Field positions and roles of the recognised columns, in field order, so that a row is
/// checked left to right and its first bad field is the one reported.
#[derive(Debug)]
struct Header {
    len: usize,
    /// Whether the file is a general one (it has `phi_i_deg` and `phi_o_deg`).
    general: bool,
    columns: Vec<(usize, Role)>,
    /// Every header name, for messages about extra fields.
    names: Vec<String>,
}

impl Header {
    fn parse(source: &Path, line: u64, record: &csv::ByteRecord) -> Result<Self, LoadError> {
        let names: Vec<String> =
            text_fields(source, line, record, |i| format!("header field {}", i + 1))?
                .into_iter()
                .map(str::to_owned)
                .collect();
        let found = header_list(&names);
        let at = |column: &str, kind| LoadError::new(source, Some(line), Some(column), kind);
        let find = |wanted: &str| -> Result<Option<usize>, LoadError> {
            let mut hits = names.iter().enumerate().filter(|(_, n)| *n == wanted);
            let first = hits.next().map(|(i, _)| i);
            if let (Some(first), Some((second, _))) = (first, hits.next()) {
                return Err(at(
                    wanted,
                    LoadErrorKind::DuplicateColumn {
                        first: first + 1,
                        second: second + 1,
                    },
                ));
            }
            Ok(first)
        };
        let required = |wanted: &str| -> Result<usize, LoadError> {
            find(wanted)?.ok_or_else(|| {
                at(
                    wanted,
                    LoadErrorKind::MissingColumn {
                        found: found.clone(),
                    },
                )
            })
        };
        // A column whose absence changes how the file is read rather than failing it: its
        // name in another case is refused, not ignored.
        let optional = |wanted: &str| -> Result<Option<usize>, LoadError> {
            let Some(i) = find(wanted)? else {
                return match names.iter().position(|n| n.eq_ignore_ascii_case(wanted)) {
                    Some(field) => Err(at(
                        wanted,
                        LoadErrorKind::CaseVariantColumn {
                            found: names[field].clone(),
                            field: field + 1,
                        },
                    )),
                    None => Ok(None),
                };
            };
            Ok(Some(i))
        };
        let (phi_i, phi_o) = (optional(COL_PHI_I)?, optional(COL_PHI_O)?);
        let general = phi_i.is_some() || phi_o.is_some();
        let mut columns = vec![
            (required(COL_THETA_I)?, Role::ThetaI),
            (required(COL_THETA_O)?, Role::ThetaO),
        ];
        let (l, sqrt_l, bsdf) = (find(COL_L)?, find(COL_SQRT_L)?, find(COL_BSDF)?);
        if general {
            columns.push((required(COL_PHI_I)?, Role::PhiI));
            columns.push((required(COL_PHI_O)?, Role::PhiO));
            if let Some(c) = l.map(|_| COL_L).or(sqrt_l.map(|_| COL_SQRT_L)) {
                return Err(at(c, LoadErrorKind::ValueOfOtherForm { general: true }));
            }
            let value = bsdf.ok_or_else(|| {
                at(
                    COL_BSDF,
                    LoadErrorKind::MissingColumn {
                        found: found.clone(),
                    },
                )
            })?;
            columns.push((value, Role::Value(ValueColumn::Bsdf)));
        } else {
            if bsdf.is_some() {
                return Err(at(
                    COL_BSDF,
                    LoadErrorKind::ValueOfOtherForm { general: false },
                ));
            }
            let value = match (l, sqrt_l) {
                (Some(i), None) => (i, ValueColumn::L),
                (None, Some(i)) => (i, ValueColumn::SqrtL),
                (Some(_), Some(_)) => return Err(at(COL_SQRT_L, LoadErrorKind::BothValueColumns)),
                (None, None) => {
                    return Err(at(
                        "L or sqrt_L",
                        LoadErrorKind::MissingValueColumn {
                            found: found.clone(),
                        },
                    ));
                }
            };
            columns.push((value.0, Role::Value(value.1)));
        }
        columns.extend(optional(COL_SAMPLE)?.map(|i| (i, Role::Sample)));
        columns.extend(optional(COL_WEIGHT)?.map(|i| (i, Role::Weight)));
        columns.sort_unstable_by_key(|c| c.0);
        Ok(Self {
            len: names.len(),
            general,
            columns,
            names,
        })
    }

    /// Validates one data row into its sample name and measurement: every recognised field
    /// as `data-format.md` says, and a `sqrt_L` whose square `L` overflows, or underflows to 0
    /// while it is not 0, refused.
    fn row<'r>(
        &self,
        source: &Path,
        line: u64,
        record: &'r csv::ByteRecord,
    ) -> Result<(&'r str, Measurement), LoadError> {
        let err = |column: &str, kind| LoadError::new(source, Some(line), Some(column), kind);
        if record.len() > self.len {
            return Err(err(
                &format!("extra field {}", self.len + 1),
                LoadErrorKind::LongRow {
                    found: record.len(),
                    expected: self.len,
                },
            ));
        }
        // Every field is checked for UTF-8, including those of unrecognised columns.
        let fields = text_fields(source, line, record, |i| column_label(&self.names, i))?;
        if fields.len() < self.len {
            return Err(err(
                &column_label(&self.names, fields.len()),
                LoadErrorKind::ShortRow {
                    found: fields.len(),
                    expected: self.len,
                },
            ));
        }
        let mut name = "";
        let (mut theta_i, mut phi_i, mut theta_o, mut phi_o) = (0.0, 0.0, 0.0, 0.0);
        let (mut value, mut weight) = (0.0, 1.0);
        for &(i, role) in &self.columns {
            let column = self.names[i].as_str();
            if role == Role::Sample {
                if fields[i].is_empty() {
                    return Err(err(COL_SAMPLE, LoadErrorKind::EmptySampleName));
                }
                name = fields[i];
                continue;
            }
            let x = parse_finite(fields[i]).map_err(|kind| err(column, kind))?;
            let range = |ok: bool, range: &'static str| {
                if ok {
                    Ok(x)
                } else {
                    Err(err(
                        column,
                        LoadErrorKind::AngleOutOfRange { value: x, range },
                    ))
                }
            };
            match role {
                Role::ThetaI if self.general => theta_i = range(theta_in_range(x), THETA_RANGE)?,
                Role::ThetaI => theta_i = range(theta_i_in_range(x), THETA_I_RANGE)?,
                Role::ThetaO if self.general => theta_o = range(theta_in_range(x), THETA_RANGE)?,
                Role::ThetaO => theta_o = range(theta_o_in_range(x), THETA_O_RANGE)?,
                Role::PhiI => phi_i = x,
                Role::PhiO => phi_o = x,
                Role::Value(_) | Role::Weight if x < 0.0 => {
                    return Err(err(column, LoadErrorKind::Negative(x)));
                }
                Role::Value(ValueColumn::SqrtL) if !(x * x).is_finite() => {
                    return Err(err(
                        column,
                        LoadErrorKind::Overflow {
                            value: x,
                            derived: "L = sqrt_L^2",
                        },
                    ));
                }
                Role::Value(ValueColumn::SqrtL) if x * x == 0.0 && x != 0.0 => {
                    return Err(err(
                        column,
                        LoadErrorKind::Underflow {
                            value: x,
                            derived: "L = sqrt_L^2",
                        },
                    ));
                }
                Role::Value(ValueColumn::SqrtL) => value = x * x,
                Role::Value(_) => value = x,
                Role::Weight => weight = x,
                Role::Sample => unreachable!("handled above"),
            }
        }
        // `-0` is accepted as zero; store it as +0.
        let (value, weight) = (value + 0.0, weight + 0.0);
        let point = if self.general {
            Measurement::spherical((theta_i, phi_i), (theta_o, phi_o), value, weight)
        } else {
            Measurement::in_plane(theta_i, theta_o, value, weight)
        };
        Ok((name, point))
    }
}

/// Parses a decimal number that must be finite and, when it is not 0, must not read as 0: a
/// nonzero number of magnitude at most about 2.47e-324 (`1e-400`) is refused, where a subnormal
/// one (`1e-310`) is read as it is.
pub(crate) fn parse_finite(text: &str) -> Result<f64, LoadErrorKind> {
    if text.is_empty() {
        return Err(LoadErrorKind::EmptyValue);
    }
    let x: f64 = text
        .parse()
        .map_err(|_| LoadErrorKind::NotANumber(text.to_owned()))?;
    if !x.is_finite() {
        return Err(LoadErrorKind::NonFinite(text.to_owned()));
    }
    // A zero read from digits that are not all zero (the exponent aside) underflowed.
    if x == 0.0
        && text
            .bytes()
            .take_while(|&b| b != b'e' && b != b'E')
            .any(|b| matches!(b, b'1'..=b'9'))
    {
        return Err(LoadErrorKind::Unrepresentable(text.to_owned()));
    }
    Ok(x)
}

impl Dataset {
    /// Reads and validates the measurement file at `path` (see [`load_path`]).
    pub fn load(path: &Path) -> Result<Self, LoadError> {
        load_path(path)
    }

    /// The sample called `name`, or an error naming the file and the samples it has.
    /// A file without a `sample` column has no sample to select, not even `""`, its unnamed one
    /// (data-format.md).
    pub fn sample(&self, name: &str) -> Result<&Sample, LoadError> {
        let unnamed = self.samples.iter().all(|s| s.name.is_empty());
        if let Some(sample) = self.samples.iter().find(|s| s.name == name && !unnamed) {
            return Ok(sample);
        }
        let kind = if unnamed {
            LoadErrorKind::NoSampleColumn(name.to_owned())
        } else {
            let available = self
                .samples
                .iter()
                .map(|s| format!("'{}'", s.name))
                .collect::<Vec<_>>()
                .join(", ");
            LoadErrorKind::UnknownSample {
                name: name.to_owned(),
                available,
            }
        };
        Err(LoadError::new(&self.source, None, Some(COL_SAMPLE), kind))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::{Measured, Quantity};

    fn load(text: &str) -> Result<Dataset, LoadError> {
        load_bytes(Path::new("t.csv"), text.as_bytes())
    }

    fn kind_at(text: &str) -> (Option<u64>, Option<String>, LoadErrorKind) {
        let e = load(text).unwrap_err();
        (e.line, e.column, e.kind)
    }

    /// In-memory columns read to the same dataset as the file with the same fields, and their
    /// problems are placed as that file's would be (row k on line k + 2).
    #[test]
    fn columns_read_as_the_file_of_the_same_fields() {
        let text = "sample,theta_i_deg,theta_o_deg,L,weight\na,0,180,0.1,1\nb,30,200.5,3e-7,0.5\n\
                    a,60,140,2,1\n";
        let file = load(text).unwrap();
        let num = |v: &[f64]| Column::Numbers(v.to_vec());
        let mut columns = vec![
            (
                "sample".to_string(),
                Column::Text(vec!["a".into(), "b".into(), "a".into()]),
            ),
            ("theta_i_deg".to_string(), num(&[0.0, 30.0, 60.0])),
            ("theta_o_deg".to_string(), num(&[180.0, 200.5, 140.0])),
            ("L".to_string(), num(&[0.1, 3e-7, 2.0])),
            ("weight".to_string(), num(&[1.0, 0.5, 1.0])),
        ];
        let table = load_columns(Path::new("t.csv"), &columns).unwrap();
        assert_eq!(table, file);
        columns[3].1 = num(&[0.1, f64::NAN, 2.0]);
        let e = load_columns(Path::new("<arrays>"), &columns).unwrap_err();
        assert_eq!((e.line, e.column.as_deref()), (Some(3), Some("L")));
        assert!(matches!(e.kind, LoadErrorKind::NonFinite(_)));
        columns[3].1 = num(&[0.1, 2.0]);
        let e = load_columns(Path::new("<arrays>"), &columns).unwrap_err();
        assert_eq!((e.line, e.column.as_deref()), (None, Some("L")));
        assert_eq!(
            e.kind,
            LoadErrorKind::ColumnLength {
                found: 2,
                expected: 3
            }
        );
    }

    #[test]
    fn minimal_file_without_sample_column() {
        let d = load("theta_i_deg,theta_o_deg,L\n0,180,2.5\n30,200,0\n").unwrap();
        assert_eq!(d.samples.len(), 1);
        assert_eq!(d.samples[0].name, "");
        assert_eq!(
            d.samples[0].points[0],
            Measurement::in_plane(0.0, 180.0, 2.5, 1.0)
        );
    }

    #[test]
    fn sqrt_l_is_squared_and_samples_keep_first_appearance_order() {
        let text = "sqrt_L,theta_o_deg,sample,theta_i_deg,notes\n\
                    0.5,180,b,0,x\n2,181,a,0,y\n0.25,182,b,30,z\n";
        let d = load(text).unwrap();
        let names: Vec<_> = d.samples.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["b", "a"]);
        assert_eq!(d.samples[0].points.len(), 2);
        assert_eq!(d.samples[0].points[0].value, 0.25);
        assert_eq!(d.samples[0].points[1].value, 0.0625);
        assert_eq!(d.samples[0].points[1].in_plane_angles().unwrap().0, 30.0);
        assert_eq!(d.samples[1].points[0].value, 4.0);
    }

    #[test]
    fn bom_whitespace_blank_lines_comments_crlf_and_quotes() {
        let text = "\u{feff}# made by hand\r\n sample , theta_i_deg,theta_o_deg , L ,weight\r\n\
                    \r\n   \r\n\"frosted, fine\", 10 ,\t170.5, 1e-3 , 0\r\n# comment\r\n\
                    \"frosted, fine\",10,171,2E-3,2.5\r\n";
        let d = load(text).unwrap();
        assert_eq!(d.samples.len(), 1);
        let s = &d.samples[0];
        assert_eq!(s.name, "frosted, fine");
        assert_eq!(s.points.len(), 2);
        assert_eq!(s.points[0].in_plane_angles().unwrap().1, 170.5);
        assert_eq!(s.points[0].value, 1e-3);
        assert_eq!(s.points[0].weight, 0.0);
        assert_eq!(s.points[1].weight, 2.5);
    }

    #[test]
    fn line_numbers_count_comments_and_blank_lines() {
        let text = "# c\n\ntheta_i_deg,theta_o_deg,L\n0,180,1\n# c\n\n0,180,x\n";
        let (line, column, kind) = kind_at(text);
        assert_eq!(line, Some(7));
        assert_eq!(column.as_deref(), Some("L"));
        assert_eq!(kind, LoadErrorKind::NotANumber("x".into()));
        let crlf = text.replace('\n', "\r\n");
        assert_eq!(kind_at(&crlf).0, Some(7));
        let quoted = "\n\nsample,theta_i_deg,theta_o_deg,L\r\n\r\n\"a\n\nb\",0,180,1\n  \n\n\"c\",0,180,-1\n";
        assert_eq!(kind_at(quoted).0, Some(10));
    }

    /// Line ends are `\n` or `\r\n`; a lone `\r` (old Mac line ends) is not one, so such a
    /// file is one line, whose header lacks the value column.
    #[test]
    fn a_lone_carriage_return_does_not_end_a_line() {
        let (line, column, kind) = kind_at("theta_i_deg,theta_o_deg,L\r0,180,1\r30,200,-1\r");
        assert_eq!(line, Some(1));
        assert_eq!(column.as_deref(), Some("L or sqrt_L"));
        assert!(
            matches!(kind, LoadErrorKind::MissingValueColumn { .. }),
            "{kind:?}"
        );
        let (line, column, _) = kind_at("theta_i_deg,theta_o_deg,L\n0,180,1\r\n30,200,1\r0\n");
        assert_eq!(line, Some(3));
        assert_eq!(column.as_deref(), Some("L"));
        let d = load("sample,theta_i_deg,theta_o_deg,L\r\n\"a\",0,180,1\r\n\r\n\"b\" ,0,180,2\r\n")
            .unwrap();
        let names: Vec<_> = d.samples.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["a", "b"]);
    }

    /// A line holding one quoted empty field is a row, not a blank line.
    #[test]
    fn a_quoted_empty_field_is_not_a_blank_line() {
        let (line, column, kind) = kind_at("theta_i_deg,theta_o_deg,L\n0,180,1\n\"\"\n");
        assert_eq!(line, Some(3));
        assert_eq!(column.as_deref(), Some("theta_o_deg"));
        assert!(matches!(kind, LoadErrorKind::ShortRow { .. }), "{kind:?}");
        let (line, _, _) = kind_at("theta_i_deg,theta_o_deg,L\r\n0,180,1\r\n\r\n\"  \"\r\n");
        assert_eq!(line, Some(4));
    }

    /// RFC 4180: only whitespace may follow a quoted field's closing quote, and a quoted field
    /// must be closed. The row is placed at its first line, the field by its column, and a
    /// problem of an earlier row comes first.
    #[test]
    fn text_after_a_closing_quote_or_an_unclosed_quote_is_refused() {
        let head = "sample,theta_i_deg,theta_o_deg,L\n";
        let at = |text: &str| {
            let (line, column, kind) = kind_at(text);
            (line, column.unwrap_or_default(), kind)
        };
        let after = LoadErrorKind::TextAfterQuote;
        assert_eq!(
            at(&format!("{head}a,0,180,1\n\"a\"b,0,180,1\n")),
            (Some(3), "sample".into(), after.clone())
        );
        assert_eq!(
            at(&format!("{head}\"a\nb\",\"0\" 1,180,1\n")),
            (Some(2), "theta_i_deg".into(), after.clone())
        );
        assert_eq!(
            at("\"sample\"x,theta_i_deg,theta_o_deg,L\n"),
            (Some(1), "header field 1".into(), after.clone())
        );
        assert_eq!(
            at(&format!("{head}a,0,180,1,\"x\"y\n")),
            (Some(2), "extra field 5".into(), after)
        );
        assert_eq!(
            at(&format!("{head}a,0,180,1\n\"b,0,180,1\n")),
            (Some(3), "sample".into(), LoadErrorKind::UnterminatedQuote)
        );
        assert_eq!(
            at(&format!("{head}a,0,180,x\n\"a\"b,0,180,1\n")),
            (Some(2), "L".into(), LoadErrorKind::NotANumber("x".into()))
        );
        let d = load(&format!("{head}\"a\" \t,0,180,1\r\n\"b\"\"\",0,180,1\n")).unwrap();
        let names: Vec<_> = d.samples.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["a", "b\""]);
    }

    #[test]
    fn hash_only_starts_a_comment_at_the_start_of_a_line_outside_quotes() {
        let text = "sample,theta_i_deg,theta_o_deg,L\n\"a\n#b\",0,180,1\n\
                    # x, \"y\n#c,0,180,2\n a#,0,180,3\n";
        let d = load(text).unwrap();
        let names: Vec<_> = d.samples.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["a\n#b", "a#"]);
        let e = load("theta_i_deg,theta_o_deg,L\n\"x\"\"#\n#y\",0,180\n").unwrap_err();
        assert_eq!(e.line, Some(2));
    }

    #[test]
    fn angle_ranges_are_half_open_and_open() {
        let ok = "theta_i_deg,theta_o_deg,L\n0,90.0001,1\n89.999,269.999,1\n";
        assert!(load(ok).is_ok());
        for (row, col) in [
            ("90,180,1", COL_THETA_I),
            ("-1,180,1", COL_THETA_I),
            ("0,90,1", COL_THETA_O),
            ("0,270,1", COL_THETA_O),
            ("0,45,1", COL_THETA_O),
        ] {
            let (line, column, kind) = kind_at(&format!("theta_i_deg,theta_o_deg,L\n{row}\n"));
            assert_eq!(line, Some(2), "{row}");
            assert_eq!(column.as_deref(), Some(col), "{row}");
            assert!(
                matches!(kind, LoadErrorKind::AngleOutOfRange { .. }),
                "{row}"
            );
        }
    }

    #[test]
    fn first_bad_field_from_the_left_is_reported() {
        let (_, column, _) = kind_at("L,theta_i_deg,theta_o_deg\n-1,95,45\n");
        assert_eq!(column.as_deref(), Some("L"));
        let (_, column, _) = kind_at("theta_i_deg,sample,theta_o_deg,L\n95,,180,1\n");
        assert_eq!(column.as_deref(), Some("theta_i_deg"));
    }

    #[test]
    fn a_row_missing_only_an_unrecognised_field_is_short_too() {
        let (line, column, kind) = kind_at("theta_i_deg,theta_o_deg,L,notes\n0,180,1,x\n0,180,1\n");
        assert_eq!((line, column.as_deref()), (Some(3), Some("notes")));
        assert_eq!(
            kind,
            LoadErrorKind::ShortRow {
                found: 3,
                expected: 4
            }
        );
    }

    #[test]
    fn bad_fields_name_their_column() {
        let h = "sample,theta_i_deg,theta_o_deg,L,weight\n";
        let cases = [
            ("a,0,180,nan,1", "L", LoadErrorKind::NonFinite("nan".into())),
            (
                "a,0,180,-inf,1",
                "L",
                LoadErrorKind::NonFinite("-inf".into()),
            ),
            ("a,0,180,-0.5,1", "L", LoadErrorKind::Negative(-0.5)),
            ("a,0,180,1,-2", "weight", LoadErrorKind::Negative(-2.0)),
            ("a,,180,1,1", "theta_i_deg", LoadErrorKind::EmptyValue),
            (
                "a,0,18O,1,1",
                "theta_o_deg",
                LoadErrorKind::NotANumber("18O".into()),
            ),
            ("  ,0,180,1,1", "sample", LoadErrorKind::EmptySampleName),
            (
                "a,0,180",
                "L",
                LoadErrorKind::ShortRow {
                    found: 3,
                    expected: 5,
                },
            ),
            (
                "a,0,180,1,1,7",
                "extra field 6",
                LoadErrorKind::LongRow {
                    found: 6,
                    expected: 5,
                },
            ),
        ];
        for (row, col, want) in cases {
            let (line, column, kind) = kind_at(&format!("{h}{row}\n"));
            assert_eq!(line, Some(2), "{row}");
            assert_eq!(column.as_deref(), Some(col), "{row}");
            assert_eq!(kind, want, "{row}");
        }
    }

    /// A finite `sqrt_L` whose square overflows is refused at its line and column, not passed
    /// on as an infinite `L`; the largest one whose square is finite is read.
    #[test]
    fn sqrt_l_whose_square_overflows_is_refused() {
        let h = "theta_i_deg,theta_o_deg,sqrt_L\n0,180,1\n";
        let (line, column, kind) = kind_at(&format!("{h}30,170,1e200\n"));
        assert_eq!((line, column.as_deref()), (Some(3), Some("sqrt_L")));
        assert_eq!(
            kind,
            LoadErrorKind::Overflow {
                value: 1e200,
                derived: "L = sqrt_L^2"
            }
        );
        let e = load(&format!("{h}30,170,1e200\n")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.csv:3: column 'sqrt_L': 1e200 is too large: L = sqrt_L^2 overflows to infinity"
        );
        let d = load(&format!("{h}30,170,1e154\n")).unwrap();
        assert_eq!(d.samples[0].points[1].value, 1e154 * 1e154);
    }

    /// A nonzero number that reads as 0 (`1e-400`) is refused in every numeric column, and so
    /// is a nonzero `sqrt_L` whose square underflows to 0; zeros however written, subnormal
    /// values and a `sqrt_L` whose square is subnormal are read as they are.
    #[test]
    fn nonzero_numbers_that_read_as_zero_are_refused() {
        let h = "sample,theta_i_deg,theta_o_deg,L,weight\na,0,180,1,1\n";
        for (row, col, text) in [
            ("a,0,180,1e-400,1", "L", "1e-400"),
            ("a,0,180,1,1e-400", "weight", "1e-400"),
            ("a,-0.0001e-321,180,1,1", "theta_i_deg", "-0.0001e-321"),
            ("a,0,180,2e-324,1", "L", "2e-324"),
        ] {
            let (line, column, kind) = kind_at(&format!("{h}{row}\n"));
            assert_eq!((line, column.as_deref()), (Some(3), Some(col)), "{row}");
            assert_eq!(kind, LoadErrorKind::Unrepresentable(text.into()), "{row}");
        }
        let e = load(&format!("{h}a,0,180,1e-400,1\n")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.csv:3: column 'L': '1e-400' is not 0 but too small to be represented (magnitude at \
             most about 2.47e-324): it would read as 0"
        );
        let d = load(&format!(
            "{h}a,0,180,0e-400,0.000E+5\na,0,180,-0.0,1\na,0,180,1e-310,1\na,0,180,5e-324,1\n"
        ))
        .unwrap();
        let values: Vec<f64> = d.samples[0].points.iter().map(|p| p.value).collect();
        assert_eq!(values, [1.0, 0.0, 0.0, 1e-310, 5e-324]);
        assert_eq!(d.samples[0].points[1].weight, 0.0);
        let s = "theta_i_deg,theta_o_deg,sqrt_L\n0,180,1\n";
        let (line, column, kind) = kind_at(&format!("{s}30,170,1e-170\n"));
        assert_eq!((line, column.as_deref()), (Some(3), Some("sqrt_L")));
        assert_eq!(
            kind,
            LoadErrorKind::Underflow {
                value: 1e-170,
                derived: "L = sqrt_L^2"
            }
        );
        let e = load(&format!("{s}30,170,1e-170\n")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.csv:3: column 'sqrt_L': 1e-170 is too small: L = sqrt_L^2 underflows to 0"
        );
        let d = load(&format!("{s}30,170,1e-160\n30,170,0\n")).unwrap();
        let values: Vec<f64> = d.samples[0].points.iter().map(|p| p.value).collect();
        assert_eq!(values, [1.0, 1e-160 * 1e-160, 0.0]);
        assert!(values[1] > 0.0 && !values[1].is_normal());
    }

    /// A column with an empty header name is named by its position: a short row had said
    /// `column ''`, and a header listed in a message showed the name as nothing.
    #[test]
    fn empty_header_names_are_named_by_position() {
        let (line, column, kind) = kind_at("theta_i_deg,,theta_o_deg,L,,\n0,5,180,1\n");
        assert_eq!(
            (line, column.as_deref()),
            (Some(2), Some("field 5 (empty name)"))
        );
        assert!(matches!(kind, LoadErrorKind::ShortRow { .. }));
        let (_, column, kind) = kind_at("theta_i_deg,,L\n0,180,1\n");
        assert_eq!(column.as_deref(), Some("theta_o_deg"));
        assert!(
            kind.to_string().contains("theta_i_deg, (empty), L"),
            "{kind}"
        );
        let e = load_bytes(
            Path::new("t.csv"),
            b"theta_i_deg,theta_o_deg,L, \n0,180,1,\xff\n",
        )
        .unwrap_err();
        assert_eq!(e.column.as_deref(), Some("field 4 (empty name)"), "{e}");
        assert_eq!(e.kind, LoadErrorKind::NotUtf8);
    }

    #[test]
    fn header_problems() {
        let (line, column, kind) = kind_at("theta_i_deg,theta_o_deg\n0,180\n");
        assert_eq!((line, column.as_deref()), (Some(1), Some("L or sqrt_L")));
        assert!(matches!(kind, LoadErrorKind::MissingValueColumn { .. }));
        let (_, column, kind) = kind_at("theta_i_deg,theta_o_deg,L,sqrt_L\n0,180,1,1\n");
        assert_eq!(column.as_deref(), Some("sqrt_L"));
        assert_eq!(kind, LoadErrorKind::BothValueColumns);
        let (_, column, kind) = kind_at("theta_i_deg,L,theta_o_deg,L\n0,1,180,1\n");
        assert_eq!(column.as_deref(), Some("L"));
        assert_eq!(
            kind,
            LoadErrorKind::DuplicateColumn {
                first: 2,
                second: 4
            }
        );
        let (_, column, _) = kind_at("theta_i_deg,L\n0,1\n");
        assert_eq!(column.as_deref(), Some("theta_o_deg"));
        assert!(matches!(kind_at("").2, LoadErrorKind::Empty { .. }));
        assert!(matches!(
            kind_at("\u{feff}\n# only a comment\n\n").2,
            LoadErrorKind::Empty { .. }
        ));
        let (line, _, kind) = kind_at("# c\ntheta_i_deg,theta_o_deg,L\n\n");
        assert_eq!((line, kind), (Some(2), LoadErrorKind::NoRows));
    }

    /// Header names in messages are shown as other text of a file is: control characters
    /// escaped, long names cut, at most 20 listed. A file with lone `\r` line ends is one
    /// header line, and its whole text (with raw `\r`s that redraw the terminal line) had
    /// been echoed in the message.
    #[test]
    fn header_names_in_messages_are_escaped_and_cut() {
        let mut cr = String::from("sample,theta_i_deg,theta_o_deg,L");
        for k in 0..1000 {
            cr += &format!("\ra,{k},170,1");
        }
        let e = load(&cr).unwrap_err().to_string();
        assert!(
            e.starts_with("t.csv:1: column 'L or sqrt_L': missing"),
            "{e}"
        );
        assert!(!e.chars().any(char::is_control) && e.len() < 2000, "{e}");
        assert!(
            e.contains("L\\ra") && e.ends_with("... (3004 fields))"),
            "{e}"
        );
        let e = load("theta_i_deg,\x1b[2J,L\n0,170,1\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("theta_i_deg, \\u{1b}[2J, L"), "{e}");
        let long = "n".repeat(5000);
        let e = load(&format!("theta_i_deg,theta_o_deg,L,{long}\n0,170,1\n"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("t.csv:2: column 'nnnn") && e.len() < 200,
            "{e}"
        );
    }

    #[test]
    fn non_utf8_is_located() {
        let bytes = b"sample,theta_i_deg,theta_o_deg,L\nok,0,180,1\n\xff\xfe,0,180,1\n";
        let e = load_bytes(Path::new("t.csv"), bytes).unwrap_err();
        assert_eq!(
            (e.line, e.column.as_deref(), e.kind),
            (Some(3), Some("sample"), LoadErrorKind::NotUtf8)
        );
    }

    #[test]
    fn all_zero_weights_in_a_sample_are_rejected() {
        let text =
            "sample,theta_i_deg,theta_o_deg,L,weight\na,0,180,1,1\nb,0,180,1,0\nb,0,181,1,0\n";
        let (line, column, kind) = kind_at(text);
        assert_eq!((line, column.as_deref()), (Some(3), Some("weight")));
        assert_eq!(kind, LoadErrorKind::AllWeightsZero("b".into()));
    }

    #[test]
    fn selecting_samples() {
        let d = load("sample,theta_i_deg,theta_o_deg,L\na,0,180,1\nb,0,180,2\n").unwrap();
        assert_eq!(d.sample("b").unwrap().points[0].value, 2.0);
        let e = d.sample("c").unwrap_err();
        assert_eq!(e.column.as_deref(), Some("sample"));
        assert_eq!(
            e.to_string(),
            "t.csv: column 'sample': no sample named 'c' (the file has: 'a', 'b')"
        );
        let d = load("theta_i_deg,theta_o_deg,L\n0,180,1\n").unwrap();
        // Not even the unnamed sample's "" selects anything (data-format.md).
        for name in ["a", ""] {
            assert!(matches!(
                d.sample(name).unwrap_err().kind,
                LoadErrorKind::NoSampleColumn(_)
            ));
        }
    }

    #[test]
    fn display_format() {
        let e = load("theta_i_deg,theta_o_deg,L\n0,180,abc\n").unwrap_err();
        assert_eq!(e.to_string(), "t.csv:2: column 'L': 'abc' is not a number");
        let e = load_path(Path::new("/nonexistent/x.csv")).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("/nonexistent/x.csv: cannot read the file")
        );
    }

    /// A general file: spherical angles on both sides, reflection and transmission, any
    /// finite azimuth, the BSDF value column, and directions as the format defines them.
    #[test]
    fn general_files_read_spherical_directions_on_both_sides() {
        let text = "sample,theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,bsdf,weight\n\
                    g,30,0,30,180,2.5,1\n\
                    g,30,0,160,-720.5,0.5,2\n\
                    g,150,45,100,225,0,1\n";
        let d = load(text).unwrap();
        let points = &d.samples[0].points;
        assert_eq!(points.len(), 3);
        assert!(points.iter().all(|p| p.quantity() == Quantity::Bsdf));
        assert_eq!(d.samples[0].measured(), Measured::Bsdf);
        assert_eq!(
            points[1],
            Measurement::spherical((30.0, 0.0), (160.0, -720.5), 0.5, 2.0)
        );
        // Mirror reflection of light from outside: wo = (-wi.x, -wi.y, wi.z).
        let (wi, wo) = points[0].directions();
        let s = 30f64.to_radians().sin();
        assert!((wi.x - s).abs() < 1e-15 && wi.y.abs() < 1e-15 && wi.z > 0.0);
        assert!((wo.x + s).abs() < 1e-15 && (wo.z - wi.z).abs() < 1e-15);
        // Light from inside the glass, scattered back inside: both z < 0.
        let (wi, wo) = points[2].directions();
        assert!(wi.z < 0.0 && wo.z < 0.0);
        assert!((wi.x - wi.y).abs() < 1e-15 && wi.x > 0.0, "phi_i = 45");
    }

    /// The general form's own rules: polar angles in [0, 180] without 90, finite azimuths,
    /// both azimuth columns, `bsdf` and not `L` or `sqrt_L` (and `bsdf` only there), each
    /// error at its line and column.
    #[test]
    fn general_file_errors_name_line_and_column() {
        let head = "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,bsdf\n";
        let at = |row: &str| kind_at(&format!("{head}0,0,170,0,1\n{row}\n"));
        let (line, column, kind) = at("0,0,90,0,1");
        assert_eq!((line, column.as_deref()), (Some(3), Some("theta_o_deg")));
        assert!(matches!(kind, LoadErrorKind::AngleOutOfRange { value, .. } if value == 90.0));
        for bad in ["180.5", "-1"] {
            let (_, column, kind) = at(&format!("{bad},0,10,0,1"));
            assert_eq!(column.as_deref(), Some("theta_i_deg"));
            assert!(
                matches!(kind, LoadErrorKind::AngleOutOfRange { .. }),
                "{kind}"
            );
        }
        let (_, column, kind) = at("0,inf,10,0,1");
        assert_eq!(column.as_deref(), Some("phi_i_deg"));
        assert_eq!(kind, LoadErrorKind::NonFinite("inf".into()));
        let (_, column, kind) = at("0,0,10,nan,1");
        assert_eq!(column.as_deref(), Some("phi_o_deg"));
        assert_eq!(kind, LoadErrorKind::NonFinite("nan".into()));
        let (_, column, kind) = at("0,0,10,0,-0.5");
        assert_eq!(column.as_deref(), Some("bsdf"));
        assert_eq!(kind, LoadErrorKind::Negative(-0.5));
        let (_, column, kind) = kind_at("theta_i_deg,phi_i_deg,theta_o_deg,bsdf\n0,0,10,1\n");
        assert_eq!(column.as_deref(), Some("phi_o_deg"));
        assert!(matches!(kind, LoadErrorKind::MissingColumn { .. }));
        let (_, column, kind) =
            kind_at("theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,L\n0,0,10,0,1\n");
        assert_eq!(column.as_deref(), Some("L"));
        assert_eq!(kind, LoadErrorKind::ValueOfOtherForm { general: true });
        let (_, column, kind) = kind_at("theta_i_deg,theta_o_deg,bsdf\n0,180,1\n");
        assert_eq!(column.as_deref(), Some("bsdf"));
        assert_eq!(kind, LoadErrorKind::ValueOfOtherForm { general: false });
        let e = load(&format!("{head}0,0,90,0,1\n")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.csv:2: column 'theta_o_deg': 90 is out of range; must be in [0, 180] with 90 \
             excluded"
        );
        // Only spaces and tabs are removed around fields: a no-break space is part of it.
        let e = load(&format!("{head}0,0,10,0,1\u{a0}\n")).unwrap_err();
        assert!(e.to_string().contains("is not a number"), "{e}");
        let d = load(&format!("{head}\t0 , 0,\t10\t,0 ,  1 \r\n")).unwrap();
        assert_eq!(d.samples[0].points.len(), 1);
        // Tiny and huge values are written short, not as 300 digits.
        let e = load(&format!("{head}-1e-300,0,10,0,1\n")).unwrap_err();
        assert!(e.to_string().contains("-1e-300 is out of range"), "{e}");
        let e = load(&format!("{head}0,0,10,0,-1e-300\n")).unwrap_err();
        assert!(e.to_string().contains("-1e-300 is negative"), "{e}");
    }

    /// Files and folders read together: samples merged by name in order of first appearance,
    /// a folder's files in name order, hidden files left out, an empty folder refused.
    #[test]
    fn paths_and_folders_merge_samples_by_name() {
        let dir = std::env::temp_dir().join(format!("stfit-load-paths-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("folder")).unwrap();
        std::fs::create_dir_all(dir.join("empty")).unwrap();
        let write = |name: &str, text: &str| std::fs::write(dir.join(name), text).unwrap();
        write(
            "a.csv",
            "sample,theta_i_deg,theta_o_deg,L\nx,0,180,1\ny,0,180,2\n",
        );
        write(
            "folder/2.csv",
            "sample,theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,bsdf\nx,0,0,10,0,3\n",
        );
        write(
            "folder/1.csv",
            "sample,theta_i_deg,theta_o_deg,L\nz,0,180,4\n",
        );
        write("folder/.hidden", "not a measurement file");
        let d = load_paths(&[dir.join("a.csv"), dir.join("folder")]).unwrap();
        let names: Vec<_> = d.samples.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["x", "y", "z"]);
        assert_eq!(d.samples[0].points.len(), 2);
        assert_eq!(d.samples[0].measured(), Measured::Both);
        let e = load_paths(&[dir.join("empty")]).unwrap_err();
        assert_eq!(e.kind, LoadErrorKind::EmptyFolder);
        let e = load_paths(&[dir.join("missing.csv")]).unwrap_err();
        assert!(matches!(e.kind, LoadErrorKind::Io(_)), "{e}");
        // A file named twice, directly or through its folder, would count twice.
        for twice in [
            vec![
                dir.join("empty").join("..").join("a.csv"),
                dir.join("a.csv"),
            ],
            vec![dir.join("folder"), dir.join("folder").join("1.csv")],
        ] {
            let e = load_paths(&twice).unwrap_err();
            assert!(matches!(e.kind, LoadErrorKind::Repeated(_)), "{e}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A hard link is another path to the same file: given with the file, its measurements
    /// would count twice, as they did when files were told apart by their canonical paths.
    #[cfg(unix)]
    #[test]
    fn a_hard_link_to_a_file_given_too_is_the_file_given_twice() {
        let dir = std::env::temp_dir().join(format!("stfit-load-link-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("a.csv");
        std::fs::write(&file, "theta_i_deg,theta_o_deg,L\n0,180,1\n0,170,2\n").unwrap();
        let link = dir.join("b.csv");
        std::fs::hard_link(&file, &link).unwrap();
        let e = load_paths(&[file.clone(), link.clone()]).unwrap_err();
        assert_eq!(e.file, link);
        assert_eq!(e.kind, LoadErrorKind::Repeated(file.display().to_string()));
        let e = load_paths(std::slice::from_ref(&dir)).unwrap_err();
        assert!(matches!(e.kind, LoadErrorKind::Repeated(_)), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A file of 200,000 one-row samples reads as 200,000 samples in file order. Merging each
    /// file's samples by name had compared every name with every earlier one (100,000 samples
    /// took over a minute); the time is measured by the `load 200,000 one-row samples` bench
    /// (`cargo bench -p stfit-fit --bench fit -- load`), not here.
    #[test]
    fn many_samples_read_in_file_order() {
        let dir = std::env::temp_dir().join(format!("stfit-load-many-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let n = 200_000;
        let mut text = String::from("sample,theta_i_deg,theta_o_deg,L\n");
        for k in 0..n {
            text += &format!("s{k},0,170,1\n");
        }
        let path = dir.join("many.csv");
        std::fs::write(&path, text).unwrap();
        let d = load_paths(&[path]).unwrap();
        assert_eq!(d.samples.len(), n);
        for (k, s) in d.samples.iter().enumerate() {
            assert_eq!(s.name, format!("s{k}"));
            assert_eq!(s.points.len(), 1);
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Every weight of a sample's rows in one file may be 0 when another file gives the
    /// sample a positive weight: the rule is on the merged sample, placed at its first row.
    #[test]
    fn zero_weights_are_checked_on_samples_merged_across_files() {
        let dir = std::env::temp_dir().join(format!("stfit-load-weights-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let head = "sample,theta_i_deg,theta_o_deg,L,weight\n";
        let write = |name: &str, rows: &str| {
            let path = dir.join(name);
            std::fs::write(&path, format!("{head}{rows}")).unwrap();
            path
        };
        let tails = write("tails.csv", "a,0,180,1,0\nb,0,180,1,1\na,30,200,1,0\n");
        let peak = write("peak.csv", "a,10,190,1,2\n");
        let other = write("other.csv", "c,10,190,1,2\n");
        let d = load_paths(&[tails.clone(), peak]).unwrap();
        let names: Vec<_> = d.samples.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["a", "b"]);
        assert_eq!(d.samples[0].points.len(), 3);
        let e = load_paths(&[other, tails.clone()]).unwrap_err();
        assert_eq!((e.file, e.line), (tails, Some(2)));
        assert_eq!(e.column.as_deref(), Some(COL_WEIGHT));
        assert_eq!(e.kind, LoadErrorKind::AllWeightsZero("a".into()));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
