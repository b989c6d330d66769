"""Collaboration (chapter section 10): FIPA ACL, delegation, task allocation, constraint server."""
