# SPDX-License-Identifier: GPL-3.0-or-later
"""Walking Blender node trees (materials, world, lights): the input socket by any of its
names across versions, the socket linked into another through reroutes, a socket's
constant colour, and the Material Output node Cycles uses."""


# ---- reading node trees ------------------------------------------------------------------


def input_socket(node, *names):
    """The first input socket with one of `names` (names changed in Blender 4.0)."""
    for name in names:
        socket = node.inputs.get(name)
        if socket is not None:
            return socket
    return None


def linked_from(socket):
    """The output socket linked into `socket`, through reroutes, or None."""
    seen = 0
    while socket is not None and socket.is_linked and seen < 64:
        link = socket.links[0]
        if not link.is_valid or getattr(link, "is_muted", False):
            return None
        node = link.from_node
        if node.type == "REROUTE":
            socket = node.inputs[0]
            seen += 1
            continue
        return link.from_socket
    return None


def color_value(socket):
    v = socket.default_value
    return (float(v[0]), float(v[1]), float(v[2]))


def active_output(tree):
    """The Material Output node Cycles would use."""
    outputs = [n for n in tree.nodes if n.type == "OUTPUT_MATERIAL"]
    for preferred in ("CYCLES", "ALL"):
        for n in outputs:
            if n.is_active_output and n.target == preferred:
                return n
    for n in outputs:
        if n.target in ("CYCLES", "ALL"):
            return n
    return outputs[0] if outputs else None
