-- hostile: a write that fails (file-size limit, as on a full disk) is a clean
-- error naming the file, and the previous file stays intact.
-- expect-exit: 1
-- expect: file_size_limit\.lua:8: cannot write '.*/big\.txt': File too large
-- ulimit-f: 64
bliskrun.write_text("big.txt", "previous contents\n")
bliskrun.write_text("other.txt", "x")
bliskrun.write_text("big.txt", string.rep("0123456789abcdef", 65536))
