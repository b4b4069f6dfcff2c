/* gl_buffers.c — the buffers shaders write: each draw's fragment counter,
 * the pixel probe's records, the fragment lists of domain-overlap, the
 * Gaussian passes' records and tile counts.  This file is the one place
 * that knows how they are made, reset and read:
 *
 *  1. Shaders write them through shader storage (atomicAdd, atomicExchange,
 *     stores), never through atomic counter buffers (atomic_uint).
 *  2. They are reset by gl__buffer_fill (glClearNamedBufferSubData: a fill
 *     ordered with the draws, into the storage the shaders are bound to) and
 *     given new storage only to grow (gl__buffer_alloc once or on growth,
 *     gl__buffer_reserve); never re-specified
 *     by glNamedBufferSubData of the whole buffer or glNamedBufferData of its
 *     own size.
 *  3. They are read by gl__buffer_read, after
 *     glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT).
 *
 * Rule 3 is GL's: shader writes reach glGetBufferSubData, and a later
 * glBufferSubData waits for them, only across that barrier (glMemoryBarrier,
 * GL_BUFFER_UPDATE_BARRIER_BIT).  Rules 1 and 2 work around Mesa 22.3.6's zink
 * (docs/parity-gpu.md, "zink: lost counts and a freed buffer"; the minimal
 * program is tools/zink-counter-repro.c).  zink records which storage slots
 * hold a buffer in a bit mask that zink_set_shader_buffers sets at the
 * call's loop index instead of at start_slot + index.  Mesa binds an atomic
 * counter buffer, lowered to a storage buffer, at slot (the program's
 * storage blocks + its binding), one slot a call: so whenever a program also
 * has storage blocks (every program here: gl_prelude.glsl declares three),
 * the counter's mask, and the mask of the buffer it displaces, are wrong.  A
 * whole-buffer glBufferSubData on a buffer still in use, or a glBufferData
 * of its own size, makes zink give the buffer new storage and rebind its
 * slots through that mask; the wrong mask left the draws' descriptors on the
 * old storage.  The draws then counted into it (every fragment count after
 * the first read 0), and once it was freed, lavapipe's threads read freed
 * memory: the crash of `parity --random` on zink.
 */
#include "gl_internal.h"

void gl__buffer_alloc(GLuint *buf, size_t bytes, GLenum usage)
{
    if (!*buf) glCreateBuffers(1, buf);
    glNamedBufferData(*buf, (GLsizeiptr)(bytes ? bytes : 16), NULL, usage);
}

void gl__buffer_reserve(GLuint *buf, size_t *cap, size_t bytes, GLenum usage)
{
    if (*buf && *cap && bytes <= *cap) return;
    gl__buffer_alloc(buf, bytes, usage);
    *cap = bytes ? bytes : 16;
}

void gl__buffer_fill(GLuint buf, size_t offset, size_t bytes, uint32_t word)
{
    if (bytes) glClearNamedBufferSubData(buf, GL_R32UI, (GLintptr)offset, (GLsizeiptr)bytes, GL_RED_INTEGER, GL_UNSIGNED_INT, &word);
}

void gl__buffer_read(GLuint buf, size_t offset, size_t bytes, void *out)
{
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    if (bytes) glGetNamedBufferSubData(buf, (GLintptr)offset, (GLsizeiptr)bytes, out);
}
