#pragma once
// Keeping freed frame-sized buffers in the process instead of returning them to the kernel.

namespace multimodal_nvs {

/// Tells glibc's allocator to serve blocks up to 32 MB (its ceiling) from one heap shared by all
/// threads and to keep freed memory instead of trimming it. By default a block over 128 kB (a
/// 704x1280 frame is 1-11 MB) is mmap'ed and unmapped on free, so every frame's buffers are
/// page-faulted in afresh: on this project's virtual machines that fault cost was 80-90% of the
/// preview fill and the SSIM (113 -> 11 ms and 557 -> 49 ms CPU per 704x1280 frame). Process-wide:
/// call it once at the start of a tool that streams many large frames, before it starts threads,
/// not from a library or a nodelet sharing a manager. Returns false where the allocator is not
/// glibc's or refuses the settings.
bool retainFreedMemory();

}  // namespace multimodal_nvs
