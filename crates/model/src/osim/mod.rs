//! OpenSim .osim import (formats 30000 and 40000).
