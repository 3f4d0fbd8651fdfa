"""A description of the machine and software the benchmark ran on."""
from __future__ import annotations

import datetime
import os
import platform
import sys


def cpu_model() -> str:
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as info:
            for line in info:
                if line.lower().startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def load_average() -> str:
    try:
        return " / ".join(f"{v:.2f}" for v in os.getloadavg())
    except OSError:
        return "unknown"


def describe() -> dict[str, str]:
    import casadi
    import numpy
    import scipy
    import sympy
    return {
        "date": datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z"),
        "CPU": cpu_model(),
        "cores (nproc)": str(os.cpu_count()),
        "OS": platform.platform(),
        "Python": sys.version.split()[0],
        "versions": f"casadi {casadi.__version__}, scipy {scipy.__version__}, numpy {numpy.__version__}, "
                    f"sympy {sympy.__version__}",
        "load average at start (1/5/15 min)": load_average(),
    }
