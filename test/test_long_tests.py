"""Every rostest runs in `make test` or `make test-long`, never in both and never in neither, and
README.md's "The long tests" names every test that `make test` leaves out."""
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text()
HEADING = "\n## The long tests\n"


def long_rostests():
    """package/file of the rostests scripts/test_long runs."""
    script = (ROOT / "scripts" / "test_long").read_text()
    found = re.search(r"^LONG_ROSTESTS=\(([^)]*)\)", script, re.MULTILINE)
    assert found, "scripts/test_long has no LONG_ROSTESTS=(...) line"
    return set(found.group(1).split())


def registered_rostests():
    """package/file of the rostests registered with add_rostest (run by `make test`)."""
    registered = set()
    for cmake in (ROOT / "src").glob("*/CMakeLists.txt"):
        for path in re.findall(r"^\s*add_rostest\(\s*([^\s)]+)", cmake.read_text(),
                               re.MULTILINE):
            registered.add(f"{cmake.parent.name}/{Path(path).name}")
    return registered


def long_marked_pytests():
    """Names of the pytest tests (or modules, for `pytestmark`) marked `long`; a `long` mark
    anywhere else is reported as such, so that nothing marked escapes the README's list."""
    names = []
    files = list((ROOT / "src").glob("*/test/test_*.py")) + list(ROOT.glob("test/test_*.py"))
    for path in (p for p in files if p.resolve() != Path(__file__).resolve()):
        text = path.read_text()
        marked = re.findall(r"^[ \t]*@pytest\.mark\.long\b[^\n]*\n(?:[ \t]*@[^\n]*\n)*"
                            r"[ \t]*def (test_\w+)", text, re.MULTILINE)
        if re.search(r"^pytestmark\b.*\blong\b", text, re.MULTILINE):
            marked.append(path.name)
        if len(marked) < text.count("mark.long"):
            marked.append(f"{path.name}: a long mark on something else")
        names += marked
    return names


def test_every_rostest_runs_in_exactly_one_of_make_test_and_make_test_long():
    files = {f"{p.parent.parent.name}/{p.name}" for p in (ROOT / "src").glob("*/test/*.test")}
    long, registered = long_rostests(), registered_rostests()
    assert long and registered
    assert not long & registered, f"run by both: {sorted(long & registered)}"
    assert files == long | registered, (f"run by neither: {sorted(files - long - registered)}; "
                                        f"missing files: {sorted((long | registered) - files)}")


def test_the_readme_names_every_test_make_test_leaves_out():
    assert HEADING in README and "make test-long" in README
    section = README.split(HEADING, 1)[1].split("\n## ", 1)[0]
    missing = [spec for spec in sorted(long_rostests()) if spec.split("/")[1] not in section]
    missing += [name for name in long_marked_pytests() if name not in section]
    assert not missing, f"README.md, 'The long tests', does not name {missing}"
