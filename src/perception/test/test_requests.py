"""Keyword request extraction, physical terms, targets and text checks (thesis 000 §3.3)."""
import pytest
import yaml

from perception.requests import (KeywordConfigError, RejectedUtterance, check_text,
                                 extract_function, find_physical_terms, find_target,
                                 keyword_config_from_dict, load_keyword_config, tokenize)

from verbal_test_support import KEYWORDS

HOUSEHOLD = {"alex": "Alex", "bob": "Bob", "carol": "Carol", "dana": "Dana"}


def canonical(word):
    return HOUSEHOLD.get(word.lower())


def words_of(text):
    return [t.lower for t in tokenize(text)]


def function_of(text, keywords):
    words = words_of(text)
    match = extract_function(words, keywords, find_physical_terms(words, keywords))
    return (match.function.name, match.keyword) if match else None


@pytest.mark.parametrize("text, expected", [
    ("Chat with me, I feel bad.", ("chat", "chat")),
    ("Play a song to cheer me up", ("play_music", "song")),
    ("Cheer me up with a song", ("encourage", "cheer me up")),
    ("Please keep me company", ("chat", "keep me company")),
    ("Remind Bob about his pills", ("remind", "remind")),
    ("Tell the nurse I fell", ("report_to_caregiver", "nurse")),
    ("I have a headache and fever", ("ask_physical_request", "headache")),
    ("The weather is nice today", None),
    ("Reminded me to take my pills", ("remind", "remind")),   # inflected, as STT may hear it
    ("I am checking on Bob", ("check_status", "check")),
    ("Please talking to me", ("chat", "talk to me")),          # longest phrase at the same start
])
def test_earliest_keyword_selects_the_function(keywords, text, expected):
    assert function_of(text, keywords) == expected


def test_function_codes_match_config(keywords):
    codes = {name: f.code for name, f in keywords.functions.items()}
    assert codes == {"chat": 1, "encourage": 2, "check_status": 3, "ask_physical_request": 4,
                     "remind": 5, "play_music": 6, "report_to_caregiver": 7}


@pytest.mark.parametrize("text, terms", [
    ("I have a headache and fever", ("headache", "fever")),
    ("My sore throat is worse", ("sore throat",)),
    ("I FELL in the bathroom", ("fell",)),
    ("I fell asleep on the sofa", ()),
    ("I don't have a headache anymore", ()),
    ("No, I have a headache", ("headache",)),  # the negation is 4 words before: outside window
    ("I have no headache", ()),                # the YAML negation "no" read as a word, not False
    ("The painting is beautiful", ()),         # whole words only: "pain" is not in "painting"
])
def test_physical_terms(keywords, text, terms):
    assert find_physical_terms(words_of(text), keywords) == terms


def test_known_name_anywhere_is_the_target(keywords):
    assert find_target(tokenize("check Bob status"), keywords, canonical) == "Bob"
    assert find_target(tokenize("check bob status"), keywords, canonical) == "Bob"
    assert find_target(tokenize("Is Dana awake? check on her"), keywords, canonical) == "Dana"


def test_no_name_means_the_speaker(keywords):
    assert find_target(tokenize("Chat with me, I feel bad."), keywords, canonical) is None
    # A capitalised word outside a person slot is not taken for a name.
    assert find_target(tokenize("Play some Mozart music"), keywords, canonical) is None


@pytest.mark.parametrize("text", ["Check Zed status.", "check on Zed", "Remind Zed to eat"])
def test_unknown_name_in_person_slot_is_refused(keywords, text):
    with pytest.raises(RejectedUtterance, match="unknown target name 'Zed'"):
        find_target(tokenize(text), keywords, canonical)


@pytest.mark.parametrize("text, reason", [
    ("", "empty text"),
    (" \t\n", "empty text"),
    ("x" * 10_000, "10000 characters exceeds the limit of 500"),
    ("1234 5678", "no words"),
    ("Ich habe Kopfschmerzen und Fieber.", "does not look English"),
    ("陪我聊天", "does not look English"),
])
def test_bad_text_is_refused_with_reason(keywords, text, reason):
    with pytest.raises(RejectedUtterance, match=reason):
        check_text(text, keywords, lambda word: canonical(word) is not None)


def test_english_text_passes_the_checks(keywords):
    tokens = check_text("Chat with me, I feel bad.", keywords, lambda word: False)
    assert [t.text for t in tokens] == ["Chat", "with", "me", "I", "feel", "bad"]


def raw_config():
    return yaml.safe_load(KEYWORDS.read_text())


def test_config_with_chain_to_unknown_function_is_refused():
    data = raw_config()
    data["chains"] = {"check_status": ["fly_away"]}
    with pytest.raises(KeywordConfigError, match="chains.check_status: 'fly_away'"):
        keyword_config_from_dict(data)


def test_config_with_duplicate_codes_is_refused():
    data = raw_config()
    data["functions"]["chat"]["code"] = data["functions"]["remind"]["code"]
    with pytest.raises(KeywordConfigError, match="codes must be unique"):
        keyword_config_from_dict(data)


def test_config_with_bad_served_to_is_refused():
    data = raw_config()
    data["functions"]["chat"]["served_to"] = "nobody"
    with pytest.raises(KeywordConfigError, match="functions.chat.served_to"):
        keyword_config_from_dict(data)


def test_missing_config_file_names_the_file(tmp_path):
    missing = tmp_path / "keywords.yaml"
    with pytest.raises(KeywordConfigError, match=str(missing)):
        load_keyword_config(missing)


@pytest.mark.parametrize("field, entry", [
    ("negations", False), ("english_words", True), ("sentiment_neutral_words", False),
    ("physical_terms", 3)])
def test_config_entry_that_is_not_a_string_is_refused(field, entry):
    """YAML 1.1 reads an unquoted no/yes/on/off as a boolean: the loader must say so."""
    data = raw_config()
    data[field] = [*data[field], entry]
    with pytest.raises(KeywordConfigError, match=rf"{field}: entry {entry!r} is a "
                                                 rf"{type(entry).__name__}, not a word"):
        keyword_config_from_dict(data)


def test_unquoted_no_in_a_keyword_file_is_refused(tmp_path):
    path = tmp_path / "keywords.yaml"
    path.write_text(KEYWORDS.read_text().replace('negations: [not, "no",', "negations: [not, no,"))
    with pytest.raises(KeywordConfigError, match=r"negations: entry False is a bool.*quote it"):
        load_keyword_config(path)


def test_function_keyword_that_is_not_a_string_is_refused():
    data = raw_config()
    data["functions"]["chat"]["keywords"].append(True)
    with pytest.raises(KeywordConfigError, match=r"functions.chat: entry True is a bool"):
        keyword_config_from_dict(data)
