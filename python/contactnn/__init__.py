"""contactnn from Python: the local searches, the contact search handle, decks and CalculiX results, and network
files, with numpy arrays in and out (docs/python.md).

    import contactnn
    deck = contactnn.read_deck("hertz-slide.inp")
    scene = deck.scene(0)
    search = contactnn.contact_search(scene)
    contacts = search.update(scene.coordinates())
"""

from ._contactnn import (  # noqa: F401  (the module's interface)
    FACE_TYPES,
    LOCATION_NAMES,
    STATUS_NAMES,
    ContactSearch,
    Contacts,
    Deck,
    Error,
    FaceNetwork,
    FaceSearch,
    FormatError,
    InvalidArgument,
    IoError,
    LocalSearch,
    Network,
    NumericalError,
    Results,
    Scene,
    make_network,
    read_deck,
    read_face_network,
    read_network,
    read_results,
)

__all__ = [
    "FACE_TYPES", "LOCATION_NAMES", "STATUS_NAMES", "ContactSearch", "Contacts", "Deck", "Error",
    "FaceNetwork", "FaceSearch", "FormatError", "InvalidArgument", "IoError", "LocalSearch", "Network",
    "NumericalError", "Results", "Scene", "contact_search", "make_network", "read_deck", "read_face_network",
    "read_network", "read_results", "write_network",
]


def contact_search(scene, **options):
    """The contact search handle of a deck's scene: its faces, node ids and slave nodes (ContactSearch's options:
    capture_distance, quad4, threads, tracking)."""
    return ContactSearch(scene.face_types, scene.connectivity, ids=scene.node_ids, slave_nodes=scene.slave_ids,
                         **options)


def write_network(path, weights, thresholds, **scaling):
    """Writes a network file from weight arrays (make_network's arguments); returns the Network."""
    network = make_network(weights, thresholds, **scaling)
    network.write(str(path))
    return network
