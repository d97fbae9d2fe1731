"""Blender tests (a package, so that its conftest does not collide with tests/conftest.py when both run in one pytest)."""
