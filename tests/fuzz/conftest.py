import pytest


@pytest.fixture(scope="module")
def fuzz_base(tmp_path_factory):
    """The folder under which every example of a module gets its own working folder."""
    return tmp_path_factory.mktemp("fuzz")
