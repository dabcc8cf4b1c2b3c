"""What an author runs while writing a chapter: scaffolding, formatting, nbgrader metadata, the student edition.

``new_chapter``       scaffolds a chapter (``make chapter``)
``format_notebooks``  code cells to the book's width, stable cell ids
``install_cell``      the first code cell, which installs robokin where it is missing (Colab)
``nbgrader_metadata`` nbgrader's cell metadata from the authors' tags; the points table
``student_edition``   the nbgrader course and the student edition of every chapter (``make student``)
``build_meshes``      the stored meshes of the packaged robots

Each runs as ``python tools/authoring/<script>.py`` or ``python -m tools.authoring.<script>``. These
import the grading side (``tools.grading.course``) where they share it; the grading side never
imports this folder (``tests/test_tools_package.py``). This file imports nothing.
"""
