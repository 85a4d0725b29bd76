"""Live ROS1 in pure Python: XML-RPC with the master (xmlrpc.py), TCPROS with the other nodes (tcpros.py,
publisher.py, subscriber.py), a node joining both (node.py), and the tf source on it (source.py).

The package imports none of its modules, so that they may import each other through it without a circle:
``tftools.sources.live.ros1.source.Ros1Source``, ``tftools.sources.live.ros1.node.Node``."""
