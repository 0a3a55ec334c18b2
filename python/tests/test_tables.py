"""Energy tables computed as shards from Python (one task each) merge into the table the
command line computes in one run."""

import io

import numpy as np

import stfit

ARGS = ["tables", "--ndf", "ggx", "--alpha-grid", "0.1:0.9:3", "--mu-grid", "0.2:1:4",
        "--eta-grid", "1.2:1.8:2", "--orders", "all", "--walks", "2000", "--seed", "3"]


def test_shards_merge_into_the_cli_table(cli, tmp_path):
    whole = tmp_path / "whole.npy"
    cli(*ARGS, "--format", "npy", "--out", str(whole))
    spec_file = tmp_path / "spec.json"
    cli(*ARGS, "--shard", "1/1", "--out", str(spec_file))
    import json

    spec = json.dumps(json.loads(spec_file.read_text())["spec"])
    shards = [stfit.table_shard(spec, k, 3) for k in (1, 2, 3)]
    table = stfit.merge_table_shards(shards[::-1])
    assert table.npy() == whole.read_bytes()
    cells = np.load(io.BytesIO(table.npy()))
    assert cells.shape == (2, 1, 2, 4, 3)


def test_bad_shards_raise_value_error():
    import pytest

    with pytest.raises(ValueError, match="spec"):
        stfit.table_shard("{}", 1, 1)
    with pytest.raises(ValueError):
        stfit.merge_table_shards(["not json"])


SMALL = ["--ndf", "student-t", "--alpha-grid", "sq:0.3:0.9:2", "--gamma-grid", "2,4",
         "--mu-grid", "0.5:1:2", "--eta-grid", "1.5"]
SMALL_KW = dict(alpha_grid="sq:0.3:0.9:2", gamma_grid=[2.0, 4.0], mu_grid="0.5:1:2",
                eta_grid="1.5")


def test_tables_writes_the_cli_files_byte_for_byte(cli, tmp_path):
    """Every format, and a shard file, of a 2x2x2 single-scattering table (both sides) and a
    few-walk table: the keyword call writes exactly the bytes the command line writes."""
    for name in ("t.csv", "t.npy", "t.h"):
        ours, theirs = tmp_path / f"py-{name}", tmp_path / f"cli-{name}"
        cli("tables", *SMALL, "--out", str(theirs))
        table = stfit.tables("student-t", **SMALL_KW, out=ours)
        assert ours.read_bytes() == theirs.read_bytes(), name
        assert isinstance(table, stfit.Table)
    theirs = tmp_path / "cli-walks.txt"
    cli("tables", *SMALL, "--orders", "multiple", "--walks", "200", "--seed", "5",
        "--format", "npy", "--out", str(theirs))
    ours = tmp_path / "py-walks.txt"
    stfit.tables("student-t", **SMALL_KW, orders="multiple", walks=200, seed=5, format="npy",
                 out=ours)
    assert ours.read_bytes() == theirs.read_bytes()
    theirs = tmp_path / "cli-shard.json"
    cli("tables", *SMALL, "--side", "inside", "--shard", "2/3", "--out", str(theirs))
    text = stfit.tables("student-t", **SMALL_KW, side="inside", shard="2/3")
    assert text.encode() == theirs.read_bytes()


def test_table_spec_shards_merge_into_the_tables_call(tmp_path):
    """The spec of table_spec, computed as shards and merged, is the table of one call."""
    spec = stfit.table_spec("ggx", alpha_grid=[0.2, 0.6], mu_grid="0.5:1:2", eta_grid="1.3,2",
                            orders="all", walks=300)
    whole = stfit.tables("ggx", alpha_grid=[0.2, 0.6], mu_grid="0.5:1:2", eta_grid="1.3,2",
                         orders="all", walks=300)
    shards = [stfit.table_shard(spec, k, 2) for k in (1, 2)]
    merged = stfit.merge_table_shards(shards)
    assert merged.npy() == whole.npy()
    merged.write(tmp_path / "m.h")
    assert (tmp_path / "m.h").read_text() == whole.c_header()


def test_bad_table_options_raise_value_error(tmp_path):
    """The command line's checks, with the options named as keywords."""
    import pytest

    cases = [
        (dict(SMALL_KW, alpha_grid="0:1:3"), "alpha axis value 0"),
        (dict(SMALL_KW, alpha_grid="sq:0:1"), "START:END:COUNT"),
        (dict(SMALL_KW, mu_grid=[0.5, float("nan")]), "not a finite number"),
        (dict(SMALL_KW, eta_grid="0.8"), "eta axis value 0.8"),
        (dict(SMALL_KW, gamma_grid=None), "gamma_grid is required for ndf='student-t'"),
        (dict(SMALL_KW, walks=10), "walks and seed apply only to orders='multiple' or 'all'"),
        (dict(SMALL_KW, layout="cycles"), "alpha_grid conflicts with layout='cycles'"),
        (dict(SMALL_KW, shard="3/2"), "K/N"),
        (dict(SMALL_KW, shard="1/9"), "only 8 lines"),
        (dict(SMALL_KW, shard="1/2", format="csv"), "format does not apply to shard"),
        (dict(SMALL_KW, surface="conductor"), "eta_grid applies only to surface='dielectric'"),
        (dict(SMALL_KW, n=0.2), "n and k apply only to surface='conductor'"),
        (dict(SMALL_KW, orders="all", walks=0), "walks per cell"),
        (dict(SMALL_KW, orders="all", walks=-5), "walks: -5 is not an integer"),
        (dict(SMALL_KW, orders="all", seed=2**64), "seed: 18446744073709551616 is not"),
        (dict(SMALL_KW, alpha_grid=[]), "alpha axis has no values"),
        (dict(SMALL_KW, masking="smith"), "masking: unknown value 'smith'"),
        (dict(SMALL_KW, format="exr"), "format: unknown value 'exr'"),
    ]
    for kwargs, message in cases:
        with pytest.raises(ValueError, match=message.replace("(", r"\(")):
            stfit.tables("student-t", **kwargs, out=tmp_path / "t.csv")
        assert not (tmp_path / "t.csv").exists()
    with pytest.raises(ValueError, match="ndf: unknown value 'gauss'"):
        stfit.table_spec("gauss", **SMALL_KW)
    with pytest.raises(ValueError, match="mu_grid is required"):
        stfit.table_spec("ggx", alpha_grid="0.1", eta_grid="1.5")
    with pytest.raises(TypeError, match="alpha_grid"):
        stfit.tables("ggx", alpha_grid={"a": 1}, mu_grid="1", eta_grid="1.5")
