"""``JoinedStreamsClient``: a notebook client that adds a stream message to the output it continues."""

from __future__ import annotations

from nbclient import NotebookClient


class JoinedStreamsClient(NotebookClient):
    """nbclient's ``NotebookClient`` with one output per run of a stream, not one per message.

    nbclient makes every message an output of its own, each built and checked against the
    notebook schema (about 0.5 ms): a submission whose functions print or log on every call
    of a loop sends tens of thousands of messages (chapter 5's talkative solution: about
    40,000, in the student's kernel and in the grader kernel that calls its functions).
    A stream message that goes on with the cell's last output (the same stream) is appended
    to it: the output a notebook front end shows, and what nbconvert's ``coalesce_streams``
    makes of consecutive outputs of one stream; everything that reads a cell's streams joins
    their text. Outputs a hook captures (an ``Output`` widget) and a pending ``clear_output``
    take nbclient's own way.
    """

    def output(self, outs, msg, display_id, cell_index):
        """nbclient's ``output``, except for a stream message that continues the last output."""
        content = msg["content"]
        if (msg["msg_type"] == "stream" and outs and not self.clear_before_next_output
                and not self.output_hook_stack[msg["parent_header"].get("msg_id")]):
            last = outs[-1]
            if last.get("output_type") == "stream" and last.get("name") == content.get("name"):
                last["text"] += content.get("text", "")
                return last
        return super().output(outs, msg, display_id, cell_index)
