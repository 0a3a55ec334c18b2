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
