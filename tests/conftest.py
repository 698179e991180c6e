from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
MECHANISMS = sorted((ROOT / "mechanisms").glob("*.yaml"))


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT
