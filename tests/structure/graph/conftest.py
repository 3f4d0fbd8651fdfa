import sys
from pathlib import Path

# The shared hypothesis strategies live next to the tests, which are not a package.
sys.path.insert(0, str(Path(__file__).parent))
