//! glTF import (filled in by the scene work).
