def pytest_configure(config):
    # Registered here because pyproject.toml is not owned by the reference-model work.
    config.addinivalue_line("markers", "slow: long-running reference simulation (deselect with -m 'not slow')")
