"""Fixtures of the verbal perception tests: the workspace's keyword config and graph, the corpus
household, and Table 5-5 priorities."""
import pytest
from floorplan.semantic_graph import load_graph
from verbal_test_support import CORPUS, GRAPH, KEYWORDS, TABLE_5_5

from perception.request_corpus import load_corpus
from perception.requests import load_keyword_config
from perception.sentiment import SentimentAnalyzer
from perception.verbal_instructions import DictPeopleDirectory, InstructionBuilder, VerbalPipeline


@pytest.fixture(scope="session")
def keywords():
    return load_keyword_config(KEYWORDS)


@pytest.fixture(scope="session")
def analyser():
    return SentimentAnalyzer()


@pytest.fixture(scope="session")
def corpus():
    return load_corpus(CORPUS)


@pytest.fixture
def directory(corpus):
    people, _ = corpus
    return DictPeopleDirectory(people)


@pytest.fixture
def place_ids():
    return load_graph(GRAPH).place_ids()


@pytest.fixture
def pipeline(keywords, analyser, directory, place_ids):
    builder = InstructionBuilder(keywords, TABLE_5_5, place_ids, directory)
    return VerbalPipeline(keywords, analyser, builder, directory)
