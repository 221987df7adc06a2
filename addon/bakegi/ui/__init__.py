# SPDX-License-Identifier: GPL-3.0-or-later
"""What people click and read: preferences, the settings on the scene (properties.py),
operators, panels, and the report as text (report_text.py)."""
