"""What the store raises, importable without the database stack (the CLI's error map needs them
before it knows whether it will open a database)."""


class NotFoundError(LookupError):
    """No stored object has that id (or it belongs to someone else)."""


class ConflictError(Exception):
    """The write would replace something that exists (a pose already captured)."""
