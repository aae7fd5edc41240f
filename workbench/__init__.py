"""The workbench: the whole project in one local web page (``python -m workbench``)."""
