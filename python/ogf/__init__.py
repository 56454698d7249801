"""ogf for Python: the maps of the ogf occupancy mapper as numpy arrays.

Offline, from a file::

    import ogf
    m = ogf.load_map("out/map.ogfs")        # a map file (ogf-map --out) or a snapshot (ogf-mapper)
    m.centres, m.probability, m.cell_class   # numpy arrays, one row per cell
    m.query(1.0, 2.0, 0.5)                   # everything the filter knows about one cell
    grid = m.project()                       # the 2-D navigation grid of the default height band

Live, from a running ogf-mapper over LCM::

    client = ogf.MapClient()                 # follows OGF_MAP_DELTA
    client.wait_consistent(10.0)
    nav = ogf.NavClient()                    # follows OGF_NAV_GRID
    nav.wait_consistent(10.0); nav.grid()

See docs/python.md in the ogf sources (/usr/share/doc/ogf/python.md when installed).
"""

from ._ogf import MapClient, MapFileError, Map, NavClient, NavGrid, load_map

__all__ = ["Map", "MapClient", "MapFileError", "NavClient", "NavGrid", "load_map", "CLASS_FREE",
           "CLASS_UNKNOWN", "CLASS_OCCUPIED", "COST_UNKNOWN"]

#: Values of Map.cell_class and NavGrid.column_class.
CLASS_FREE = -1
CLASS_UNKNOWN = 0
CLASS_OCCUPIED = 1
#: NavGrid.cost of a column nothing is known about (as in a ROS OccupancyGrid).
COST_UNKNOWN = -1
