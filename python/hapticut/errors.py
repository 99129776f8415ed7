"""The error the library raises: the file and line it concerns, when it does, and what was expected."""


class HapticutError(Exception):
    """A failure reported by Hapticut's library, such as a malformed model file.

    str(error) reads like a compiler's message ("heart.obj:3: vertex index 3 is out of range"), so an
    editor can jump to it; `file` and `line` are None when the problem is not about a file or a line.
    """

    def __init__(self, text, file=None, line=None, message=None):
        super().__init__(text)
        self.file = file
        self.line = line
        self.message = message if message is not None else text
